//! Frame output (DESIGN §4–5): one multi-layer OpenEXR per frame (linear
//! RGBA, Z depth, normal, object id) and an sRGB PNG, both with bytes that
//! depend only on the pixels, written atomically.
//!
//! Conventions:
//! - `Image::rgba` is linear colour as seen (the renderer composites the
//!   background in) with A = coverage by geometry. The EXR stores all four
//!   channels as given; the PNG is the picture as seen: sRGB RGB, no alpha.
//! - An image with zero width or height is rejected with `InvalidInput` by
//!   every writer: neither format can hold an empty image, and an error is
//!   more honest than a made-up 1×1 frame.
//! - EXR channels: `R G B A` (f32), `Z` (f32 depth), `N.X N.Y N.Z` (f32
//!   normal), `id` (u32 object id); one part, no layer name, scan lines,
//!   ZIP (16-line blocks, lossless, compressed here at zlib's fastest
//!   level), increasing line order: the blocks are compressed in parallel
//!   but written in line order, so the bytes never depend on thread
//!   scheduling.

use std::io::{self, Cursor};
use std::path::Path;
use std::sync::OnceLock;

use exr::block::chunk::{Chunk, CompressedBlock, CompressedScanLineBlock};
use exr::block::writer::ChunksWriter;
use exr::image::write::layers::{LayersWriter, WritableLayers};
use exr::prelude::{
    AnyChannel, AnyChannels, Blocks, Compression, Encoding, FlatSamples, Image as ExrImage, Layer,
    LayerAttributes, LineOrder, ReadChannels, ReadLayers, SmallVec, Vec2, WritableImage,
};
use image::codecs::png::{CompressionType, FilterType, PngEncoder};
use image::{ExtendedColorType, ImageEncoder};
use rayon::prelude::*;

use crate::atomic::write_atomic;

/// EXR channel holding the object id (u32).
pub const ID_CHANNEL: &str = "id";
/// EXR channel holding the depth (f32), the name compositors expect.
pub const DEPTH_CHANNEL: &str = "Z";
/// EXR channels holding the world-space normal (f32).
pub const NORMAL_CHANNELS: [&str; 3] = ["N.X", "N.Y", "N.Z"];
/// EXR channels of a denoised frame's albedo (the names OIDN's tools
/// and compositors look for).
pub const ALBEDO_CHANNELS: [&str; 3] = ["albedo.R", "albedo.G", "albedo.B"];
/// EXR channels of a denoised frame's colour as rendered, before the
/// denoiser (the master keeps both).
pub const NOISY_CHANNELS: [&str; 4] = ["noisy.R", "noisy.G", "noisy.B", "noisy.A"];

/// A rendered frame: linear RGBA plus the AOV layers.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Linear RGBA, row-major, top row first; A is coverage by geometry.
    pub rgba: Vec<[f32; 4]>,
    /// Distance along the primary ray of the nearest hit, `f32::INFINITY` for none.
    pub depth: Vec<f32>,
    /// World-space shading normal at the nearest hit, 0 for none.
    pub normal: Vec<[f32; 3]>,
    /// Object id of the nearest hit, `u32::MAX` for none.
    pub object: Vec<u32>,
    /// The reflectance of the surface the pixel's centre ray meets (its
    /// BSDF's albedo, textures included), 1 for none: what the denoiser
    /// divides the light by (all 1 in a frame not denoised).
    pub albedo: Vec<[f32; 3]>,
    /// The variance of the pixel's mean luminance over its samples (0
    /// for one sample): how noisy the pixel is.
    pub variance: Vec<f32>,
    /// The colour as rendered, when the denoiser replaced it.
    pub noisy: Option<Vec<[f32; 4]>>,
}

impl Image {
    /// A frame where nothing was hit: transparent black, infinite depth,
    /// zero normal, no object. Any size is accepted (0×0 included); writers
    /// reject the empty ones.
    pub fn new(width: u32, height: u32) -> Image {
        let n = (width as usize).saturating_mul(height as usize);
        Image {
            width,
            height,
            rgba: vec![[0.0; 4]; n],
            depth: vec![f32::INFINITY; n],
            normal: vec![[0.0; 3]; n],
            object: vec![u32::MAX; n],
            albedo: vec![[1.0; 3]; n],
            variance: vec![0.0; n],
            noisy: None,
        }
    }

    /// Number of pixels, `width × height`.
    pub fn len(&self) -> usize {
        (self.width as usize).saturating_mul(self.height as usize)
    }

    /// Whether the image has no pixels.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

fn invalid_input(msg: impl std::fmt::Display) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg.to_string())
}

/// Prefixes an encoding error with the file it was meant for.
fn naming(path: &Path, e: io::Error) -> io::Error {
    io::Error::new(e.kind(), format!("cannot write {}: {e}", path.display()))
}

/// Checks what both writers need: a non-empty image whose buffers match its
/// size, so a bad frame becomes an error instead of a panic or a corrupt file.
fn validate(img: &Image) -> io::Result<()> {
    if img.is_empty() {
        return Err(invalid_input(format!(
            "image is {}x{}, empty images cannot be written",
            img.width, img.height
        )));
    }
    // OpenEXR stores the data window in i32.
    if img.width > i32::MAX as u32 || img.height > i32::MAX as u32 {
        return Err(invalid_input("image is too large"));
    }
    let n = img.len();
    let lens = [
        ("rgba", img.rgba.len()),
        ("depth", img.depth.len()),
        ("normal", img.normal.len()),
        ("object", img.object.len()),
        ("albedo", img.albedo.len()),
        ("variance", img.variance.len()),
        ("noisy", img.noisy.as_ref().map_or(n, Vec::len)),
    ];
    for (name, len) in lens {
        if len != n {
            return Err(invalid_input(format!(
                "{name} has {len} pixels, {}x{} needs {n}",
                img.width, img.height
            )));
        }
    }
    Ok(())
}

/// Turns an exr writing error into an io error.
fn exr_encode_error(e: exr::error::Error) -> io::Error {
    match e {
        exr::error::Error::Io(e) => e,
        other => io::Error::new(io::ErrorKind::InvalidInput, format!("{other}")),
    }
}

/// Turns an exr reading error into an io error that names the file.
fn exr_read_error(path: &Path, e: exr::error::Error) -> io::Error {
    match e {
        exr::error::Error::Io(e) => {
            io::Error::new(e.kind(), format!("cannot read {}: {e}", path.display()))
        }
        other => io::Error::new(
            io::ErrorKind::InvalidData,
            format!("cannot read {}: {other}", path.display()),
        ),
    }
}

/// Encodes the frame as EXR bytes in memory. Its 16-line blocks are
/// compressed in parallel on the current rayon pool and written in
/// increasing line order whatever finishes first, so the same image
/// always gives the same bytes (tested against one thread).
pub fn encode_exr(img: &Image) -> io::Result<Vec<u8>> {
    validate(img)?;
    let f32_channel = |name: &str, f: &dyn Fn(usize) -> f32| {
        AnyChannel::new(name, FlatSamples::F32((0..img.len()).map(f).collect()))
    };
    let mut channels = vec![
        f32_channel("R", &|i| img.rgba[i][0]),
        f32_channel("G", &|i| img.rgba[i][1]),
        f32_channel("B", &|i| img.rgba[i][2]),
        f32_channel("A", &|i| img.rgba[i][3]),
        f32_channel(DEPTH_CHANNEL, &|i| img.depth[i]),
        f32_channel(NORMAL_CHANNELS[0], &|i| img.normal[i][0]),
        f32_channel(NORMAL_CHANNELS[1], &|i| img.normal[i][1]),
        f32_channel(NORMAL_CHANNELS[2], &|i| img.normal[i][2]),
        AnyChannel::new(ID_CHANNEL, FlatSamples::U32(img.object.clone())),
    ];
    // A denoised frame keeps what the denoiser read: the colour as
    // rendered and the albedo (a frame not denoised, its bytes as before).
    if let Some(noisy) = &img.noisy {
        for (c, name) in NOISY_CHANNELS.iter().enumerate() {
            channels.push(f32_channel(name, &|i| noisy[i][c]));
        }
        for (c, name) in ALBEDO_CHANNELS.iter().enumerate() {
            channels.push(f32_channel(name, &|i| img.albedo[i][c]));
        }
    }
    let encoding = Encoding {
        compression: Compression::ZIP16,
        blocks: Blocks::ScanLines,
        line_order: LineOrder::Increasing,
    };
    let layer = Layer::new(
        Vec2(img.width as usize, img.height as usize),
        LayerAttributes::default(),
        encoding,
        // The file format requires channels sorted by name.
        AnyChannels::sort(SmallVec::from_vec(channels)),
    );
    let image = ExrImage::from_layer(layer);
    let headers = image.write().infer_meta_data();
    let layers = image.layer_data.create_writer(&headers);
    let mut buf = Cursor::new(Vec::new());
    exr::block::write(&mut buf, headers, true, |meta, chunks| {
        let blocks: Vec<_> = meta
            .collect_ordered_block_data(|i| layers.extract_uncompressed_block(&meta.headers, i))
            .collect();
        let compressed: Vec<_> = blocks
            .into_par_iter()
            .map(|(i, block)| (i, zip_chunk(block)))
            .collect();
        for (i, chunk) in compressed {
            chunks.write_chunk(i, chunk?)?;
        }
        Ok(())
    })
    .map_err(exr_encode_error)?;
    Ok(buf.into_inner())
}

/// A block of 16 lines (one layer, every channel 32 bits) as OpenEXR's
/// ZIP compression stores it: the little-endian bytes split into the even
/// and the odd ones, each byte as its difference to the one before, and
/// zlib at miniz's fastest level (issue 45: a third of the time of the
/// exr crate's level 4, files 6 % larger: a film frame in 15 ms instead of
/// 46). Kept raw where that is not smaller, as the format allows.
fn zip_chunk(block: exr::block::UncompressedBlock) -> exr::error::Result<Chunk> {
    let mut raw = block.data;
    if cfg!(target_endian = "big") {
        raw.chunks_exact_mut(4).for_each(<[u8]>::reverse);
    }
    let half = raw.len().div_ceil(2);
    let mut packed = vec![0; raw.len()];
    for (i, &b) in raw.iter().enumerate() {
        packed[i / 2 + (i % 2) * half] = b;
    }
    let mut previous = packed.first().copied().unwrap_or(0);
    for b in packed.iter_mut().skip(1) {
        let current = *b;
        *b = current.wrapping_sub(previous).wrapping_add(128);
        previous = current;
    }
    let zipped = miniz_oxide::deflate::compress_to_vec_zlib(&packed, 1);
    let y = i32::try_from(block.index.pixel_position.y())
        .map_err(|_| exr::error::Error::Invalid("image too tall".into()))?;
    Ok(Chunk {
        layer_index: block.index.layer,
        compressed_block: CompressedBlock::ScanLine(CompressedScanLineBlock {
            compressed_pixels_le: if zipped.len() < raw.len() {
                zipped
            } else {
                raw
            },
            y_coordinate: y,
        }),
    })
}

/// Writes the frame as one multi-layer EXR (see the module docs), atomically.
pub fn write_exr(img: &Image, path: &Path) -> io::Result<()> {
    let bytes = encode_exr(img).map_err(|e| naming(path, e))?;
    write_atomic(path, &bytes)
}

/// Encodes the frame as 8-bit sRGB RGB PNG bytes in memory. No alpha: the
/// renderer's colour already has the background composited in, so a PNG
/// alpha would only make the sky transparent in viewers (A is in the EXR).
/// The fast deflate (issue 45): a third of the default's time for files
/// 1.4× as large (the EXR is the master); the bytes are a function of the
/// pixels alone, as before.
pub fn encode_png(img: &Image) -> io::Result<Vec<u8>> {
    validate(img)?;
    let pixels = srgb8_pixels(img);
    let mut bytes = Vec::new();
    PngEncoder::new_with_quality(&mut bytes, CompressionType::Fast, FilterType::Adaptive)
        .write_image(&pixels, img.width, img.height, ExtendedColorType::Rgb8)
        .map_err(|e| io::Error::new(io::ErrorKind::InvalidInput, e.to_string()))?;
    Ok(bytes)
}

/// The frame's colour as 8-bit sRGB, three bytes a pixel, row after row:
/// what its PNG holds (and the video is made of).
pub fn srgb8_pixels(img: &Image) -> Vec<u8> {
    img.rgba
        .iter()
        .flat_map(|&[r, g, b, _]| [srgb8(r), srgb8(g), srgb8(b)])
        .collect()
}

/// Writes the frame as an 8-bit sRGB RGB PNG (see `encode_png`), atomically.
pub fn write_png(img: &Image, path: &Path) -> io::Result<()> {
    let bytes = encode_png(img).map_err(|e| naming(path, e))?;
    write_atomic(path, &bytes)
}

/// An image format lmfilm writes, in one place (issue 55): its file
/// extension and its encoder. A new format is a variant here; the film
/// folder's stages ask [`ImageFormat::ALL`] and each one's stage.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ImageFormat {
    /// The master: linear half floats, zlib-compressed.
    Exr,
    /// 8-bit sRGB, what video encoders and viewers read.
    Png,
}

impl ImageFormat {
    pub const ALL: [ImageFormat; 2] = [ImageFormat::Png, ImageFormat::Exr];

    /// Its file extension, lower case, without the dot.
    pub const fn extension(self) -> &'static str {
        match self {
            ImageFormat::Exr => "exr",
            ImageFormat::Png => "png",
        }
    }

    /// The image encoded as a file of this format.
    pub fn encode(self, img: &Image) -> io::Result<Vec<u8>> {
        match self {
            ImageFormat::Exr => encode_exr(img),
            ImageFormat::Png => encode_png(img),
        }
    }

    /// The format a path's extension names (any case), None for another.
    pub fn of_path(path: &Path) -> Option<ImageFormat> {
        let ext = path.extension()?.to_str()?;
        Self::ALL
            .into_iter()
            .find(|f| f.extension().eq_ignore_ascii_case(ext))
    }

    /// The extensions lmfilm writes, for messages: ".png or .exr".
    pub fn listed() -> String {
        let all: Vec<String> = Self::ALL
            .iter()
            .map(|f| format!(".{}", f.extension()))
            .collect();
        all.join(" or ")
    }
}

/// Writes the image in the format its extension names (any case), else
/// an InvalidInput error naming the formats lmfilm writes.
pub fn write(img: &Image, path: &Path) -> io::Result<()> {
    match ImageFormat::of_path(path) {
        Some(ImageFormat::Png) => write_png(img, path),
        Some(ImageFormat::Exr) => write_exr(img, path),
        None => Err(invalid_input(format!(
            "unsupported extension, expected {}",
            ImageFormat::listed()
        ))),
    }
}

/// Linear to 8-bit sRGB (IEC 61966-2-1 transfer), clamped to [0, 1] (NaN as 0) and rounded:
/// [`srgb8_by_formula`]'s byte, found among the least values that give
/// each byte (the formula is monotone: checked over every f32 in [0, 1]),
/// eight comparisons instead of a `powf` (a frame's PNG took 7 ms on it).
pub fn srgb8(linear: f32) -> u8 {
    static LEAST: OnceLock<[f32; 255]> = OnceLock::new();
    let least = LEAST.get_or_init(|| {
        std::array::from_fn(|v| {
            // The first f32 of [0, 1] (ordered as its bits) whose byte is
            // at least v + 1.
            let (mut lo, mut hi) = (0u32, 1.0f32.to_bits());
            while lo < hi {
                let mid = lo + (hi - lo) / 2;
                if usize::from(srgb8_by_formula(f32::from_bits(mid))) > v {
                    hi = mid;
                } else {
                    lo = mid + 1;
                }
            }
            f32::from_bits(lo)
        })
    });
    let l = if linear.is_nan() {
        0.0
    } else {
        linear.clamp(0.0, 1.0)
    };
    least.partition_point(|&t| t <= l) as u8
}

/// [`srgb8`] by the standard's formula.
fn srgb8_by_formula(l: f32) -> u8 {
    let s = if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    // `as` saturates, so a result a hair outside [0, 1] cannot wrap.
    (s * 255.0 + 0.5) as u8
}

/// 8-bit sRGB to linear, the inverse of [`srgb8`]: `srgb8(linear8(s)) == s`
/// for every `s`, so an sRGB image composed into a frame comes out of
/// the PNG writer unchanged.
pub fn linear8(s: u8) -> f32 {
    let s = f32::from(s) / 255.0;
    if s <= 0.040_45 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

/// The most bytes an EXR or PNG of `pixels` pixels that lmfilm writes
/// can take: the EXR's 36 bytes a pixel (RGBA, Z, N.X/N.Y/N.Z as f32,
/// `id` as u32), stored raw where ZIP does not shrink a block, its block
/// tables (16 bytes a block of 16 lines: at most 1 a pixel) and 64 KiB of
/// headers; a PNG (3 bytes a pixel and a filter byte a row, deflated) is
/// smaller. The bound every reader of a frame's files reads at most.
pub fn max_file_bytes(pixels: u64) -> u64 {
    pixels.saturating_mul(37).saturating_add(1 << 16)
}

/// Reads a frame written by `write_exr` back: R, G, B required; A (default
/// 1), Z (∞), N.X/N.Y/N.Z (0), `id` (u32::MAX), albedo.R/G/B (1) and
/// noisy.R/G/B/A (none) optional. The first layer
/// is used; RGB/Z/N may be stored as f16, f32 or u32, `id` must be u32.
/// Only a regular file is read, of at most [`max_file_bytes`] of the
/// default `--max-pixels` (`source::read_file`: a pipe or a device is
/// refused, never waited on).
pub fn read_exr_layers(path: &Path) -> io::Result<Image> {
    let bad = |msg: String| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!("cannot read {}: {msg}", path.display()),
        )
    };
    let limit = max_file_bytes(crate::lsys::Limits::default().pixels);
    let bytes = crate::source::read_file(path, limit)
        .map_err(|e| io::Error::new(e.kind(), format!("cannot read {}: {e}", path.display())))?;
    let exr = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| exr_read_error(path, e))?;
    let layer = exr.layer_data;
    let (w, h) = (layer.size.width(), layer.size.height());
    let (width, height) = match (u32::try_from(w), u32::try_from(h)) {
        (Ok(a), Ok(b)) => (a, b),
        _ => return Err(bad(format!("size {w}x{h} too large"))),
    };
    let mut img = Image::new(width, height);
    let n = img.len();
    let find = |name: &str| {
        layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == name)
            .map(|c| &c.sample_data)
    };
    let floats = |name: &str, required: bool| -> io::Result<Option<Vec<f32>>> {
        match find(name) {
            None if required => Err(bad(format!("missing channel {name}"))),
            None => Ok(None),
            Some(s) => {
                let v: Vec<f32> = match s {
                    // Bit-exact: no conversion for f32.
                    FlatSamples::F32(v) => v.clone(),
                    other => other.values_as_f32().collect(),
                };
                if v.len() != n {
                    return Err(bad(format!("channel {name} has {} samples", v.len())));
                }
                Ok(Some(v))
            }
        }
    };
    for (k, name) in ["R", "G", "B", "A"].into_iter().enumerate() {
        let values = floats(name, k < 3)?;
        let default = if k == 3 { 1.0 } else { 0.0 };
        for (i, px) in img.rgba.iter_mut().enumerate() {
            px[k] = values.as_ref().map_or(default, |v| v[i]);
        }
    }
    if let Some(v) = floats(DEPTH_CHANNEL, false)? {
        img.depth = v;
    }
    for (k, name) in NORMAL_CHANNELS.into_iter().enumerate() {
        if let Some(v) = floats(name, false)? {
            for (px, x) in img.normal.iter_mut().zip(v) {
                px[k] = x;
            }
        }
    }
    for (k, name) in ALBEDO_CHANNELS.into_iter().enumerate() {
        if let Some(v) = floats(name, false)? {
            for (px, x) in img.albedo.iter_mut().zip(v) {
                px[k] = x;
            }
        }
    }
    if floats(NOISY_CHANNELS[0], false)?.is_some() {
        let mut noisy = vec![[0.0f32; 4]; n];
        for (k, name) in NOISY_CHANNELS.into_iter().enumerate() {
            let v = floats(name, true)?.unwrap_or_default();
            for (px, x) in noisy.iter_mut().zip(v) {
                px[k] = x;
            }
        }
        img.noisy = Some(noisy);
    }
    match find(ID_CHANNEL) {
        None => {}
        Some(FlatSamples::U32(v)) if v.len() == n => img.object = v.clone(),
        Some(FlatSamples::U32(v)) => {
            return Err(bad(format!("channel {ID_CHANNEL} has {} samples", v.len())))
        }
        Some(_) => return Err(bad(format!("channel {ID_CHANNEL} is not u32"))),
    }
    Ok(img)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table gives the formula's byte at every 1021st f32 of [0, 1]
    /// and at every f32 of each stride where the byte changes (so at each
    /// byte's least value); all of them, about a billion, were checked
    /// once in a release build (2026-12-05, the ignored test below).
    #[test]
    fn srgb8_by_table_is_the_formula() {
        let same = |b: u32| {
            let l = f32::from_bits(b);
            assert_eq!(srgb8(l), srgb8_by_formula(l), "{l:e}");
            srgb8(l)
        };
        let one = 1.0f32.to_bits();
        let mut changes = 0;
        let mut last = (0, same(0));
        for b in (1021..one).step_by(1021).chain([one]) {
            let v = same(b);
            if v != last.1 {
                (last.0..b).for_each(|b| {
                    same(b);
                });
                changes += 1;
            }
            last = (b, v);
        }
        assert_eq!((changes, last.1), (255, 255));
    }

    /// Every f32 of [0, 1]: `cargo test --release -- --ignored exhaustive`.
    #[test]
    #[ignore]
    fn srgb8_by_table_is_the_formula_exhaustive() {
        for b in 0..=1.0f32.to_bits() {
            let l = f32::from_bits(b);
            assert_eq!(srgb8(l), srgb8_by_formula(l), "{l:e}");
        }
    }

    #[test]
    fn exr_bytes_do_not_depend_on_the_thread_count() {
        let (w, h) = (97, 211); // 14 blocks of 16 lines, the last short
        let mut img = Image::new(w, h);
        let mut x = 0x9e37_79b9_u32;
        for i in 0..img.len() {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            let v = (x % 10_000) as f32 / 977.0;
            img.rgba[i] = [v, v * 0.5, (i % w as usize) as f32, 1.0];
            img.depth[i] = v + i as f32;
            img.normal[i] = [v.sin(), v.cos(), 0.25];
            img.object[i] = x % 7;
        }
        let on = |threads| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| encode_exr(&img).unwrap())
        };
        let one = on(1);
        assert_eq!(one, on(3));
        assert_eq!(one, encode_exr(&img).unwrap());
    }
}
