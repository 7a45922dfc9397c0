//! Labels: the labels files of the open recordings and the labeling tools (`labeling`), the label
//! proposals from physics (`proposals`), and the losses per label (`losses`). Proposals return what
//! they ask of the labels (`proposals::Asked`); the state carries it out.

pub mod labeling;
pub mod losses;
pub mod proposals;
