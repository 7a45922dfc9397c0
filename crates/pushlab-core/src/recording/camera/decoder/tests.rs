#![allow(clippy::unwrap_used)]

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

use super::super::{EncodedImage, FrameSource, ImageFormat, RawEncoding};
use super::*;

const WAIT: Duration = Duration::from_secs(10);

/// A stream of `width`×`height` mono8 frames whose pixels all hold the frame's index; frame
/// `corrupt` is a JPEG with a garbage body. Counts the frames read.
struct Counted {
    width: u32,
    height: u32,
    corrupt: Option<usize>,
    reads: Arc<AtomicUsize>,
}

struct CountedReader {
    width: u32,
    height: u32,
    corrupt: Option<usize>,
    reads: Arc<AtomicUsize>,
}

impl FrameSource for Counted {
    fn reader(&self) -> Box<dyn FrameReader> {
        Box::new(CountedReader {
            width: self.width,
            height: self.height,
            corrupt: self.corrupt,
            reads: Arc::clone(&self.reads),
        })
    }

    fn location(&self) -> PathBuf {
        PathBuf::from("counted")
    }
}

impl FrameReader for CountedReader {
    fn read(&mut self, index: usize) -> Result<EncodedImage, FrameProblem> {
        self.reads.fetch_add(1, Ordering::SeqCst);
        if Some(index) == self.corrupt {
            return Ok(EncodedImage {
                format: ImageFormat::Jpeg,
                bytes: vec![0xFF, 0xD8, 0xFF, 0xE0, 1, 2, 3],
            });
        }
        Ok(EncodedImage {
            format: ImageFormat::Raw {
                encoding: RawEncoding::Mono8,
                width: self.width,
                height: self.height,
                step: self.width,
                big_endian: false,
            },
            bytes: vec![index as u8; (self.width * self.height) as usize],
        })
    }
}

fn stream(frames: usize, corrupt: Option<usize>) -> (Arc<CameraStream>, Arc<AtomicUsize>) {
    let reads = Arc::new(AtomicUsize::new(0));
    let source = Counted {
        width: 64,
        height: 32,
        corrupt,
        reads: Arc::clone(&reads),
    };
    let times = (0..frames).map(|i| i as f64 / 30.0).collect();
    let stream = CameraStream::new("cam".into(), times, Arc::new(source));
    (Arc::new(stream), reads)
}

/// Bytes of one decoded 64×32 frame.
const FRAME_BYTES: usize = 64 * 32 * 4;

#[test]
fn a_wanted_frame_is_decoded_on_the_worker_and_then_cached() {
    let (stream, reads) = stream(10, None);
    let decoder = FrameDecoder::new(DEFAULT_BUDGET_BYTES);
    assert!(
        decoder.get(&stream, 7).is_none(),
        "nothing is decoded unasked"
    );
    let image = decoder.wait_for(&stream, 7, WAIT).unwrap().unwrap();
    assert_eq!((image.width, image.height), (64, 32));
    assert_eq!(image.pixel(5, 5), Some([7, 7, 7, 255]), "frame 7's pixels");
    assert_eq!(
        decoder.get(&stream, 7).unwrap().unwrap().pixel(0, 0),
        Some([7, 7, 7, 255])
    );
    assert_eq!(
        reads.load(Ordering::SeqCst),
        1,
        "read once, then from the cache"
    );
    assert_eq!(decoder.cached_bytes(), FRAME_BYTES);
}

#[test]
fn prefetched_frames_are_ready_before_they_are_shown() {
    let (stream, reads) = stream(30, None);
    let decoder = FrameDecoder::new(DEFAULT_BUDGET_BYTES);
    decoder.want((3..9).map(|i| (Arc::clone(&stream), i)).collect());
    let deadline = Instant::now() + WAIT;
    while decoder.is_busy() && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(2));
    }
    for i in 3..9 {
        let image = decoder.get(&stream, i).expect("prefetched").unwrap();
        assert_eq!(image.pixel(1, 1), Some([i as u8, i as u8, i as u8, 255]));
    }
    assert!(decoder.get(&stream, 9).is_none());
    assert_eq!(reads.load(Ordering::SeqCst), 6);
}

#[test]
fn the_cache_stays_within_its_budget_and_keeps_the_frames_wanted_now() {
    let (stream, _) = stream(100, None);
    let budget = 5 * FRAME_BYTES;
    let decoder = FrameDecoder::new(budget);
    for i in 0..40 {
        decoder.wait_for(&stream, i, WAIT).unwrap().unwrap();
        assert!(
            decoder.cached_bytes() <= budget,
            "frame {i}: {}",
            decoder.cached_bytes()
        );
    }
    // The last frames played are kept, the first forgotten.
    assert!(decoder.get(&stream, 39).is_some());
    assert!(decoder.get(&stream, 0).is_none());
    // A wish larger than the budget still has every frame it names, for as long as it is wanted.
    decoder.want((50..58).map(|i| (Arc::clone(&stream), i)).collect());
    let deadline = Instant::now() + WAIT;
    while decoder.is_busy() && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(2));
    }
    assert!((50..58).all(|i| decoder.get(&stream, i).is_some()));
    assert_eq!(
        decoder.cached_bytes(),
        8 * FRAME_BYTES,
        "only the wanted frames"
    );
}

#[test]
fn a_corrupt_frame_is_an_error_of_its_own_and_the_next_frames_decode() {
    let (stream, reads) = stream(10, Some(4));
    let decoder = FrameDecoder::new(DEFAULT_BUDGET_BYTES);
    let error = decoder.wait_for(&stream, 4, WAIT).unwrap().unwrap_err();
    assert!(
        error.to_string().contains("not a readable jpeg image"),
        "{error}"
    );
    // Asked again, the error comes from the cache: the frame is not read again.
    assert!(decoder.wait_for(&stream, 4, WAIT).unwrap().is_err());
    assert_eq!(reads.load(Ordering::SeqCst), 1);
    let next = decoder.wait_for(&stream, 5, WAIT).unwrap().unwrap();
    assert_eq!(next.pixel(0, 0), Some([5, 5, 5, 255]));
}

#[test]
fn clearing_forgets_every_frame() {
    let (stream, _) = stream(10, None);
    let decoder = FrameDecoder::new(DEFAULT_BUDGET_BYTES);
    decoder.wait_for(&stream, 2, WAIT).unwrap().unwrap();
    decoder.clear();
    assert!(decoder.get(&stream, 2).is_none());
    assert_eq!(decoder.cached_bytes(), 0);
    assert!(!decoder.is_busy());
}

/// A browser tab cannot start the worker: the decoder decodes on the caller, the frame shown
/// first and then the prefetch, one frame for each drawn frame's `want`.
#[test]
fn without_a_worker_each_want_decodes_the_next_frame_on_the_caller() {
    let (stream, reads) = stream(30, Some(5));
    let decoder = FrameDecoder::on_caller(DEFAULT_BUDGET_BYTES);
    let wanted: Vec<_> = (3..7).map(|i| (Arc::clone(&stream), i)).collect();
    decoder.want(wanted.clone());
    let shown = decoder
        .get(&stream, 3)
        .expect("the frame shown, at once")
        .unwrap();
    assert_eq!(shown.pixel(1, 1), Some([3, 3, 3, 255]));
    assert!(decoder.get(&stream, 4).is_none(), "one frame a call");
    assert!(decoder.is_busy(), "the prefetch is still to come");
    // The next drawn frames want the same: the prefetch follows, the corrupt frame as its error.
    for _ in 0..3 {
        decoder.want(wanted.clone());
    }
    assert!(!decoder.is_busy());
    assert_eq!(
        decoder.get(&stream, 4).unwrap().unwrap().pixel(0, 0),
        Some([4, 4, 4, 255])
    );
    assert!(decoder.get(&stream, 5).unwrap().is_err());
    assert_eq!(reads.load(Ordering::SeqCst), 4);
    // A seek's wait decodes at once rather than waiting for a worker.
    let image = decoder.wait_for(&stream, 20, WAIT).unwrap().unwrap();
    assert_eq!(image.pixel(0, 0), Some([20, 20, 20, 255]));
}
