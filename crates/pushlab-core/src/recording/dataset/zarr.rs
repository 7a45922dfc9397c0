//! Zarr v2 arrays on disk, as Diffusion Policy's replay buffers store them: a folder with a
//! `.zarray` (JSON: shape, chunks, dtype, compressor, fill value, order) and one file per chunk
//! named by its grid index (`3.0`, or `3/0` with the `/` separator). Zarr lets a chunk that is
//! absent hold the fill value; pushlab refuses it (`DatasetProblem::MissingChunk`), since no
//! recording is made of fill values and zeros would be read as poses. Chunks are decoded with
//! [`super::blosc`] or the plain zstd and LZ4 codecs of numcodecs; filters and Fortran order
//! (which those buffers never use) are refused by name.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::blosc;
use super::error::DatasetError;
use super::problem::DatasetProblem;
use crate::json_problem;
use crate::recording::progress::Progress;

/// One zarr v2 array, its metadata read and checked; the values are read on demand.
#[derive(Clone, Debug)]
pub struct ZarrArray {
    dir: PathBuf,
    /// Elements along each dimension.
    pub shape: Vec<usize>,
    chunks: Vec<usize>,
    /// The element type.
    pub dtype: Dtype,
    compressor: Compressor,
    fill: f64,
    separator: char,
}

/// An element type of numpy's typestring (`<f4`, `|u1`, `<i8`, `|b1` …).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dtype {
    kind: char,
    size: usize,
    big_endian: bool,
}

impl Dtype {
    fn parse(text: &str) -> Option<Self> {
        let mut chars = text.chars();
        let order = chars.next()?;
        let kind = chars.next()?;
        let size: usize = chars.as_str().parse().ok()?;
        let ok = match kind {
            'f' => matches!(size, 4 | 8),
            'i' | 'u' => matches!(size, 1 | 2 | 4 | 8),
            'b' => size == 1,
            _ => false,
        };
        (ok && matches!(order, '<' | '>' | '|')).then_some(Self {
            kind,
            size,
            big_endian: order == '>',
        })
    }

    /// Whether the elements are bytes (images).
    pub fn is_byte(&self) -> bool {
        self.kind == 'u' && self.size == 1
    }

    fn value(&self, bytes: &[u8]) -> f64 {
        let mut b = [0u8; 8];
        b[..self.size].copy_from_slice(bytes);
        if self.big_endian {
            b[..self.size].reverse();
        }
        match (self.kind, self.size) {
            ('f', 4) => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            ('f', _) => f64::from_le_bytes(b),
            ('i', n) => {
                let shift = 64 - 8 * n as u32;
                ((i64::from_le_bytes(b) << shift) >> shift) as f64
            }
            _ => u64::from_le_bytes(b) as f64,
        }
    }
}

#[derive(Clone, Debug)]
enum Compressor {
    None,
    Blosc,
    Zstd,
    Lz4,
}

#[derive(Deserialize)]
struct Meta {
    zarr_format: u32,
    shape: Vec<usize>,
    chunks: Vec<usize>,
    dtype: serde_json::Value,
    compressor: Option<serde_json::Value>,
    fill_value: serde_json::Value,
    order: String,
    filters: Option<serde_json::Value>,
    #[serde(default)]
    dimension_separator: Option<String>,
}

/// Whether `dir` is a zarr v2 array (holds a `.zarray`).
pub fn is_array(dir: &Path) -> bool {
    crate::files::is_file(&dir.join(".zarray"))
}

impl ZarrArray {
    /// Reads and checks the array's `.zarray`; errors name that file and the field.
    pub fn open(dir: &Path) -> Result<Self, DatasetError> {
        let meta_path = dir.join(".zarray");
        let fail = |problem| DatasetError::Problem {
            path: meta_path.clone(),
            problem,
        };
        let field = |field: &str, why: String| {
            fail(DatasetProblem::Field {
                field: field.to_owned(),
                why,
            })
        };
        let text = crate::files::read(&meta_path).map_err(|e| DatasetError::io(&meta_path, e))?;
        let meta: Meta = json_problem::from_file_bytes(&text)
            .map_err(|problem| fail(DatasetProblem::Json(problem)))?;
        if meta.zarr_format != 2 {
            return Err(field(
                "zarr_format",
                format!("{}, expected 2", meta.zarr_format),
            ));
        }
        if meta.shape.len() != meta.chunks.len() || meta.shape.is_empty() {
            return Err(field(
                "chunks",
                "expected one chunk length per dimension".into(),
            ));
        }
        if meta.chunks.contains(&0) {
            return Err(field("chunks", "a chunk length is 0".into()));
        }
        let Some(dtype) = meta.dtype.as_str().and_then(Dtype::parse) else {
            return Err(field(
                "dtype",
                format!("{}, expected a number type such as \"<f4\"", meta.dtype),
            ));
        };
        if meta.order != "C" {
            return Err(field("order", format!("'{}', expected \"C\"", meta.order)));
        }
        if meta.filters.as_ref().is_some_and(|f| !f.is_null()) {
            return Err(field(
                "filters",
                "filters are not supported, expected null".into(),
            ));
        }
        let compressor = match &meta.compressor {
            None => Compressor::None,
            Some(c) => match c.get("id").and_then(serde_json::Value::as_str) {
                Some("blosc") => Compressor::Blosc,
                Some("zstd") => Compressor::Zstd,
                Some("lz4") => Compressor::Lz4,
                other => {
                    return Err(field(
                        "compressor",
                        format!("{other:?} is not supported, expected blosc, zstd, lz4 or null"),
                    ));
                }
            },
        };
        let fill = match &meta.fill_value {
            serde_json::Value::Number(n) => n.as_f64().unwrap_or(0.0),
            serde_json::Value::String(s) if s == "NaN" => f64::NAN,
            serde_json::Value::Bool(b) => f64::from(u8::from(*b)),
            _ => 0.0,
        };
        let separator = match meta.dimension_separator.as_deref() {
            None | Some(".") => '.',
            Some("/") => '/',
            Some(other) => {
                return Err(field(
                    "dimension_separator",
                    format!("'{other}', expected \".\" or \"/\""),
                ));
            }
        };
        Ok(Self {
            dir: dir.to_path_buf(),
            shape: meta.shape,
            chunks: meta.chunks,
            dtype,
            compressor,
            fill,
            separator,
        })
    }

    /// Values per element of the first dimension (per frame): the product of the other dimensions.
    pub fn width(&self) -> usize {
        self.shape[1..].iter().product()
    }

    /// Elements of a chunk along each dimension.
    pub fn chunk_shape(&self) -> &[usize] {
        &self.chunks
    }

    /// The array's folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The decoded bytes of chunk `index` along the first dimension of an array chunked along it
    /// only (an image array: whole frames per chunk); a chunk file that is missing is an error.
    pub fn read_time_chunk(&self, index: usize) -> Result<Vec<u8>, DatasetError> {
        let chunk_len: usize = self.chunks.iter().product::<usize>() * self.dtype.size;
        let mut key = index.to_string();
        for _ in 1..self.shape.len() {
            key.push(self.separator);
            key.push('0');
        }
        let path = self.dir.join(&key);
        if !crate::files::is_file(&path) {
            return Err(self.missing_chunk(path, index));
        }
        let raw = crate::files::read(&path).map_err(|e| DatasetError::io(&path, e))?;
        self.decode(&raw, chunk_len)
            .map_err(|problem| DatasetError::Problem { path, problem })
    }

    /// Every value, row-major, as `f64`; `progress` is told each chunk's bytes and stops the read
    /// when cancelled.
    pub fn read_f64(&self, progress: &dyn Progress) -> Result<Vec<f64>, DatasetError> {
        let total: usize = self.shape.iter().product();
        let mut out = vec![self.fill; total];
        let grid: Vec<usize> = (self.shape.iter().zip(&self.chunks))
            .map(|(s, c)| s.div_ceil(*c))
            .collect();
        let chunk_len: usize = self.chunks.iter().product();
        let mut index = vec![0usize; grid.len()];
        if grid.contains(&0) {
            return Ok(out);
        }
        loop {
            if progress.is_cancelled() {
                return Err(DatasetError::Problem {
                    path: self.dir.clone(),
                    problem: DatasetProblem::Cancelled,
                });
            }
            let key: Vec<String> = index.iter().map(usize::to_string).collect();
            let key = key.join(&self.separator.to_string());
            let path = self.dir.join(&key);
            if !crate::files::is_file(&path) {
                return Err(self.missing_chunk(path, index[0]));
            }
            let raw = crate::files::read(&path).map_err(|e| DatasetError::io(&path, e))?;
            progress.advance(raw.len() as u64);
            let bytes = self
                .decode(&raw, chunk_len * self.dtype.size)
                .map_err(|problem| DatasetError::Problem {
                    path: path.clone(),
                    problem,
                })?;
            self.place(&bytes, &index, &mut out);
            // The next chunk of the grid, last dimension fastest.
            let mut d = grid.len();
            loop {
                if d == 0 {
                    return Ok(out);
                }
                d -= 1;
                index[d] += 1;
                if index[d] < grid[d] {
                    break;
                }
                index[d] = 0;
            }
        }
    }

    /// The error for the chunk file at `path`, the `row_chunk`-th along the first dimension.
    fn missing_chunk(&self, path: PathBuf, row_chunk: usize) -> DatasetError {
        let rows = self.chunks.first().copied().unwrap_or(1);
        let start = row_chunk * rows;
        let end = (start + rows).min(self.shape.first().copied().unwrap_or(0));
        DatasetError::Problem {
            path,
            problem: DatasetProblem::MissingChunk { start, end },
        }
    }

    fn decode(&self, raw: &[u8], expected: usize) -> Result<Vec<u8>, DatasetProblem> {
        let bytes = match self.compressor {
            Compressor::None => raw.to_vec(),
            Compressor::Blosc => blosc::decompress(raw, expected)?,
            Compressor::Zstd => {
                let mut out = vec![0u8; expected];
                let n = ruzstd::decoding::FrameDecoder::new()
                    .decode_all(raw, &mut out)
                    .map_err(|e| DatasetProblem::Codec(format!("zstd: {e}")))?;
                out.truncate(n);
                out
            }
            Compressor::Lz4 => {
                // numcodecs' LZ4: the plain size (4 bytes, little-endian), then one LZ4 block.
                let body = raw.get(4..).unwrap_or_default();
                lz4_flex::block::decompress(body, expected)
                    .map_err(|e| DatasetProblem::Codec(format!("lz4: {e}")))?
            }
        };
        if bytes.len() == expected {
            Ok(bytes)
        } else {
            Err(DatasetProblem::ChunkSize {
                chunk: self.dir.display().to_string(),
                bytes: bytes.len(),
                expected,
            })
        }
    }

    /// Copies a decoded chunk's elements that lie inside the array into `out`.
    fn place(&self, bytes: &[u8], chunk_index: &[usize], out: &mut [f64]) {
        let dims = self.shape.len();
        let mut local = vec![0usize; dims];
        for element in bytes.chunks_exact(self.dtype.size) {
            let mut flat = 0;
            let mut inside = true;
            for d in 0..dims {
                let global = chunk_index[d] * self.chunks[d] + local[d];
                inside &= global < self.shape[d];
                flat = flat * self.shape[d] + global;
            }
            if inside {
                out[flat] = self.dtype.value(element);
            }
            for d in (0..dims).rev() {
                local[d] += 1;
                if local[d] < self.chunks[d] {
                    break;
                }
                local[d] = 0;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typestrings_read_little_and_big_endian_values() {
        let f4 = Dtype::parse("<f4").expect("f4");
        assert_eq!(f4.value(&1.5f32.to_le_bytes()), 1.5);
        let i8_big = Dtype::parse(">i8").expect("i8");
        assert_eq!(i8_big.value(&(-3i64).to_be_bytes()), -3.0);
        let i2 = Dtype::parse("<i2").expect("i2");
        assert_eq!(i2.value(&(-2i16).to_le_bytes()), -2.0);
        assert!(Dtype::parse("|u1").is_some_and(|d| d.is_byte()));
        assert!(Dtype::parse("<c8").is_none() && Dtype::parse("<f2").is_none());
    }
}
