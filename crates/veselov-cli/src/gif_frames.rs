//! Animated GIFs of plots, written frame by frame from RGB buffers.
//!
//! Plots hold few colours: white, greys of text and axes, and anti-aliased
//! blends of a few line colours with white. Every frame is mapped through
//! one fixed palette ([`Quantizer`]: a 6×6×6 colour cube, 24 greys and 15
//! blends of the line colour with white) by a 32 768-entry table indexed by
//! the 5 high bits of each channel, instead of a colour search per frame;
//! and a frame after the first stores only the rectangle of pixels that
//! changed, the unchanged ones inside it transparent
//! ([`AnimationEncoder::push`]); runs of pixels whose colours did not change
//! keep their indices without a lookup. A 120-frame centreline animation
//! took about 2 s with a per-frame neural-net quantisation of whole frames.

use std::borrow::Cow;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use gif::{DisposalMethod, Encoder, Frame, Repeat};

/// The palette index kept for "unchanged since the previous frame".
pub const TRANSPARENT: u8 = 255;

/// The colour of plotted lines (matplotlib's first colour), which the
/// palette holds exactly with its blends towards white.
pub const LINE_COLOUR: [u8; 3] = [31, 119, 180];

/// The fixed palette and the table mapping an RGB colour to its nearest
/// entry (nearest in squared RGB distance to the centre of the colour's
/// 5-bit cell).
pub struct Quantizer {
    palette: [[u8; 3]; 256],
    table: Vec<u8>,
}

impl Quantizer {
    /// Builds the palette and its table (for each of the 32 768 cells, the
    /// nearest of the cube's colours and of the 39 others, once per
    /// animation).
    pub fn new() -> Self {
        let mut palette = [[255, 0, 255]; 256];
        let level = |k: usize| (51 * k) as u8;
        for r in 0..6 {
            for g in 0..6 {
                for b in 0..6 {
                    palette[36 * r + 6 * g + b] = [level(r), level(g), level(b)];
                }
            }
        }
        for k in 0..24 {
            let grey = (10 + 10 * k) as u8;
            palette[216 + k] = [grey; 3];
        }
        for k in 0..15 {
            let t = k as f64 / 15.0;
            palette[240 + k] = LINE_COLOUR.map(|c| (f64::from(c) + t * (255.0 - f64::from(c))).round() as u8);
        }
        let mut table = vec![0u8; 1 << 15];
        for (cell, slot) in table.iter_mut().enumerate() {
            let centre = [(cell >> 10) & 31, (cell >> 5) & 31, cell & 31].map(|v| ((v << 3) | 4) as i32);
            let distance = |c: &[u8; 3]| -> i32 { (0..3).map(|i| (i32::from(c[i]) - centre[i]).pow(2)).sum() };
            // The nearest cube colour channel by channel (the cube is a
            // product grid), then the 39 greys and blends.
            let [r, g, b] = centre.map(|c| ((c + 25) / 51) as u8);
            let cube = 36 * r + 6 * g + b;
            *slot = (216..TRANSPARENT)
                .chain(std::iter::once(cube))
                .min_by_key(|&i| (distance(&palette[usize::from(i)]), i))
                .unwrap_or(cube);
        }
        Self { palette, table }
    }

    /// The palette index of an RGB colour.
    #[inline]
    pub fn index(&self, rgb: &[u8]) -> u8 {
        let cell = (usize::from(rgb[0] >> 3) << 10) | (usize::from(rgb[1] >> 3) << 5) | usize::from(rgb[2] >> 3);
        self.table[cell]
    }

    /// The colour of palette entry `i`.
    pub fn colour(&self, i: u8) -> [u8; 3] {
        self.palette[usize::from(i)]
    }

    /// The palette as the GIF's global colour table (256 RGB triples).
    fn table_bytes(&self) -> Vec<u8> {
        self.palette.iter().flatten().copied().collect()
    }
}

impl Default for Quantizer {
    fn default() -> Self {
        Self::new()
    }
}

/// An animated GIF being written: frames of one size, shown for `delay`
/// hundredths of a second each, looping.
pub struct AnimationEncoder {
    encoder: Encoder<BufWriter<File>>,
    quantizer: Quantizer,
    size: (u16, u16),
    delay: u16,
    /// Palette indices of the last frame written (empty before the first).
    previous: Vec<u8>,
    current: Vec<u8>,
    /// The changed rectangle's indices.
    patch: Vec<u8>,
    /// RGB bytes of the last frame written.
    previous_rgb: Vec<u8>,
}

impl AnimationEncoder {
    /// Creates the file at `path` for frames of `size` pixels.
    pub fn create(path: &Path, size: (u16, u16), delay_ms: u32) -> Result<Self, String> {
        let quantizer = Quantizer::new();
        let file = File::create(path).map_err(|e| e.to_string())?;
        let mut encoder =
            Encoder::new(BufWriter::new(file), size.0, size.1, &quantizer.table_bytes()).map_err(|e| e.to_string())?;
        encoder.set_repeat(Repeat::Infinite).map_err(|e| e.to_string())?;
        Ok(Self {
            encoder,
            quantizer,
            size,
            delay: u16::try_from(delay_ms.div_ceil(10)).unwrap_or(u16::MAX),
            previous: Vec::new(),
            current: Vec::new(),
            patch: Vec::new(),
            previous_rgb: Vec::new(),
        })
    }

    /// Appends the frame whose RGB pixels (row by row, 3 bytes each) are
    /// `rgb`: the whole frame the first time, afterwards the smallest
    /// rectangle holding every pixel whose palette index changed, unchanged
    /// pixels inside it transparent (a 1 × 1 transparent patch when nothing
    /// changed).
    pub fn push(&mut self, rgb: &[u8]) -> Result<(), String> {
        let (w, h) = (usize::from(self.size.0), usize::from(self.size.1));
        if rgb.len() != 3 * w * h {
            return Err(format!("a frame of {} bytes for {w} × {h} pixels", rgb.len()));
        }
        // The frame borrows its pixels (no copy per frame).
        let frame = if self.previous.is_empty() {
            self.current.clear();
            self.current
                .extend(rgb.chunks_exact(3).map(|p| self.quantizer.index(p)));
            Frame {
                width: self.size.0,
                height: self.size.1,
                buffer: Cow::Borrowed(self.current.as_slice()),
                ..Frame::default()
            }
        } else {
            let [left, top, width, height] = self.changed_patch(rgb, w, h);
            Frame {
                left,
                top,
                width,
                height,
                buffer: Cow::Borrowed(self.patch.as_slice()),
                transparent: Some(TRANSPARENT),
                ..Frame::default()
            }
        };
        let frame = Frame {
            delay: self.delay,
            dispose: DisposalMethod::Keep,
            ..frame
        };
        self.encoder.write_frame(&frame).map_err(|e| e.to_string())?;
        std::mem::swap(&mut self.previous, &mut self.current);
        self.previous_rgb.clear();
        self.previous_rgb.extend_from_slice(rgb);
        Ok(())
    }

    /// Writes the GIF's trailer and flushes the file, reporting a failure
    /// (an encoder merely dropped, after an error, writes its trailer and
    /// ignores what fails).
    pub fn finish(self) -> Result<(), String> {
        let mut file = self.encoder.into_inner().map_err(|e| e.to_string())?;
        file.flush().map_err(|e| e.to_string())
    }

    /// The palette indices of `rgb` into `current`, and the smallest
    /// rectangle holding the pixels whose index differs from the previous
    /// frame's, written into `patch` (unchanged pixels transparent): its
    /// left, top, width and height. Runs of [`BLOCK`] pixels whose RGB bytes
    /// equal the previous frame's keep its indices without a lookup (most of
    /// a plot does not move between frames).
    fn changed_patch(&mut self, rgb: &[u8], w: usize, h: usize) -> [u16; 4] {
        let (mut left, mut right, mut top, mut bottom) = (w, 0, h, 0);
        self.current.clear();
        for y in 0..h {
            let row = &rgb[3 * y * w..3 * (y + 1) * w];
            let old_row = &self.previous_rgb[3 * y * w..3 * (y + 1) * w];
            let old = &self.previous[y * w..(y + 1) * w];
            let (mut first, mut last) = (None, 0);
            let mut x = 0;
            while x < w {
                let n = BLOCK.min(w - x);
                let (new_rgb, old_rgb) = (&row[3 * x..3 * (x + n)], &old_row[3 * x..3 * (x + n)]);
                if same_bytes(new_rgb, old_rgb) {
                    self.current.extend_from_slice(&old[x..x + n]);
                } else {
                    for (k, p) in new_rgb.chunks_exact(3).enumerate() {
                        let index = self.quantizer.index(p);
                        if index != old[x + k] {
                            first.get_or_insert(x + k);
                            last = x + k;
                        }
                        self.current.push(index);
                    }
                }
                x += n;
            }
            if let Some(first) = first {
                left = left.min(first);
                right = right.max(last + 1);
                top = top.min(y);
                bottom = y + 1;
            }
        }
        if top >= bottom {
            (left, right, top, bottom) = (0, 1, 0, 1);
        }
        self.patch.clear();
        for y in top..bottom {
            let (old, new) = (&self.previous[y * w..(y + 1) * w], &self.current[y * w..(y + 1) * w]);
            self.patch.extend(
                old[left..right]
                    .iter()
                    .zip(&new[left..right])
                    .map(|(a, b)| if a == b { TRANSPARENT } else { *b }),
            );
        }
        let narrow = |v: usize| u16::try_from(v).unwrap_or(u16::MAX);
        [narrow(left), narrow(top), narrow(right - left), narrow(bottom - top)]
    }
}

/// Pixels compared at once with the previous frame's
/// ([`AnimationEncoder::push`]).
const BLOCK: usize = 8;

/// Whether two runs of at most [`BLOCK`] pixels are equal: a full run as
/// three 8-byte words (no call to a byte-comparison routine), a shorter
/// one byte by byte.
#[inline]
fn same_bytes(a: &[u8], b: &[u8]) -> bool {
    match (<&[u8; 3 * BLOCK]>::try_from(a), <&[u8; 3 * BLOCK]>::try_from(b)) {
        (Ok(a), Ok(b)) => {
            let word = |x: &[u8; 3 * BLOCK], k: usize| {
                u64::from_ne_bytes([
                    x[8 * k],
                    x[8 * k + 1],
                    x[8 * k + 2],
                    x[8 * k + 3],
                    x[8 * k + 4],
                    x[8 * k + 5],
                    x[8 * k + 6],
                    x[8 * k + 7],
                ])
            };
            (0..3).all(|k| word(a, k) == word(b, k))
        }
        _ => a == b,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Plot colours map to themselves (white, black, the line colour), and
    /// every colour c to an entry p nearly as close as the nearest entry q:
    /// p is the nearest to the centre m of c's 5-bit cell (|c − m| ≤ 4 per
    /// channel), so |p − c| ≤ |p − m| + |m − c| ≤ |q − m| + |m − c| ≤
    /// |q − c| + 2·4√3.
    #[test]
    fn the_palette_holds_plot_colours() {
        let q = Quantizer::new();
        for c in [[255, 255, 255], [0, 0, 0], LINE_COLOUR] {
            assert_eq!(q.colour(q.index(&c)), c);
        }
        let distance = |a: [u8; 3], b: [u8; 3]| -> f64 {
            (0..3)
                .map(|i| (f64::from(a[i]) - f64::from(b[i])).powi(2))
                .sum::<f64>()
                .sqrt()
        };
        for r in (0..256).step_by(5) {
            for g in (0..256).step_by(7) {
                for b in (0..256).step_by(3) {
                    let c = [r as u8, g as u8, b as u8];
                    let chosen = distance(q.colour(q.index(&c)), c);
                    let nearest = (0..TRANSPARENT)
                        .map(|i| distance(q.colour(i), c))
                        .fold(f64::INFINITY, f64::min);
                    assert!(
                        chosen <= nearest + 8.0 * 3f64.sqrt() + 1e-9,
                        "{c:?}: {chosen} against {nearest}"
                    );
                }
            }
        }
    }

    /// The frames decoded and composited (each patch over the last picture)
    /// equal the quantised frames that were pushed, pixel for pixel, and
    /// later frames store only the changed rectangle; with rows of whole
    /// comparison blocks and with a partial block at each row's end.
    #[test]
    fn patches_rebuild_every_frame() {
        patches_rebuild_every_frame_of_width(40);
        patches_rebuild_every_frame_of_width(37);
    }

    fn patches_rebuild_every_frame_of_width(w: usize) {
        let h = 30usize;
        let dir = crate::test_scratch::Scratch::new(&format!("gif-frames-{w}"));
        let path = dir.join("frames.gif");
        let q = Quantizer::new();
        let frames: Vec<Vec<u8>> = (0..5)
            .map(|k| {
                let mut rgb = vec![255u8; 3 * w * h];
                // A moving block of the line colour and a grey one that stays.
                for y in 5..10 {
                    for x in (3 * k)..(3 * k + 6) {
                        rgb[3 * (y * w + x)..3 * (y * w + x) + 3].copy_from_slice(&LINE_COLOUR);
                    }
                }
                for y in 20..25 {
                    for x in 30..35 {
                        rgb[3 * (y * w + x)..3 * (y * w + x) + 3].copy_from_slice(&[90, 90, 90]);
                    }
                }
                rgb
            })
            .collect();
        let mut encoder = AnimationEncoder::create(&path, (w as u16, h as u16), 80).expect("created");
        for f in &frames {
            encoder.push(f).expect("frame");
        }
        // The unchanged last frame: a 1 × 1 patch.
        encoder.push(&frames[4]).expect("frame");
        encoder.finish().expect("written");
        let mut options = gif::DecodeOptions::new();
        options.set_color_output(gif::ColorOutput::Indexed);
        let mut decoder = options.read_info(File::open(&path).expect("file")).expect("a GIF");
        let mut canvas = vec![0u8; w * h];
        let mut sizes = Vec::new();
        for expected in frames.iter().chain(std::iter::once(&frames[4])) {
            let frame = decoder.read_next_frame().expect("decoded").expect("a frame");
            let (left, top) = (usize::from(frame.left), usize::from(frame.top));
            let fw = usize::from(frame.width);
            sizes.push((frame.width, frame.height));
            for (i, &p) in frame.buffer.iter().enumerate() {
                if frame.transparent != Some(p) {
                    canvas[(top + i / fw) * w + left + i % fw] = p;
                }
            }
            let want: Vec<u8> = expected.chunks_exact(3).map(|p| q.index(p)).collect();
            assert_eq!(canvas, want);
        }
        assert_eq!(sizes[0], (w as u16, h as u16), "the first frame whole");
        assert_eq!(sizes[1], (9, 5), "the block's old and new columns, its rows");
        assert_eq!(sizes[5], (1, 1), "nothing changed");
    }
}
