//! Ctrl-C as the long commands take it: the first press sets a flag the command checks between two
//! steps (a training batch, a live message) so that it stops cleanly, keeping what it made; a
//! second press exits at once (code 130, as a shell reports an interrupted command). One handler
//! per process, installed on first use.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, Ordering};

/// Set by Ctrl-C.
static CANCEL: AtomicBool = AtomicBool::new(false);

/// The cancel flag, with the Ctrl-C handler installed on first use.
pub fn cancel_flag() -> &'static AtomicBool {
    static INSTALLED: OnceLock<()> = OnceLock::new();
    INSTALLED.get_or_init(|| {
        let installed = ctrlc::set_handler(|| {
            if CANCEL.swap(true, Ordering::SeqCst) {
                std::process::exit(130);
            }
            eprintln!("\nstopping cleanly; Ctrl-C again to quit at once");
        });
        if let Err(e) = installed {
            eprintln!("note: Ctrl-C cannot stop cleanly here ({e})");
        }
    });
    &CANCEL
}

/// Whether Ctrl-C was pressed.
pub fn cancelled() -> bool {
    CANCEL.load(Ordering::SeqCst)
}
