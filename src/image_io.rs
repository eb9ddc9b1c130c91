//! Reading and writing images.
//!
//! Everything in the renderer works on [`Rgb32Image`], a linear-radiance RGB
//! float image. It can be stored as:
//!
//! * **OpenEXR** (`.exr`): linear float32 RGB, no alpha, bit-exact round trip.
//!   Reading accepts the first layer holding `R`, `G` and `B` channels in any
//!   order, as f16, f32 or u32 samples; other channels (alpha, AOVs) are
//!   ignored.
//! * **PNG** (`.png`): 8-bit sRGB for viewing. Writing applies the sRGB OETF
//!   and clamps to `[0, 1]`; reading decodes sRGB back to linear.
//!
//! Reading refuses an image of more than [`MAX_PIXELS`] pixels, and a file shorter than its
//! header says, before allocating anything for its pixels.
//!
//! Writes are atomic: the file is encoded in memory, written to a temporary
//! file beside the target and renamed over it, so a crash or a full disk never
//! leaves a truncated file where the previous one was.

use std::ffi::OsString;
use std::fmt;
use std::fs::{self, File};
use std::io::{self, Cursor, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use exr::meta::attribute::Compression;
use exr::prelude::{ReadChannels, ReadLayers, SpecificChannels, Vec2, WritableImage};
use image::{ExtendedColorType, ImageEncoder, ImageFormat};

/// The most pixels an image read may have: those of the renderer's largest image, 16384 x 16384
/// (the scene loader's `MAX_RESOLUTION` squared), 3 GiB as [`Rgb32Image`].
pub const MAX_PIXELS: u64 = 16384 * 16384;

/// A linear-radiance RGB image with `f32` channels.
///
/// Pixels are stored row-major with row 0 at the top:
/// pixel `(x, y)` is `pixels[y * width + x]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Rgb32Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Linear RGB radiance, row-major from the top, `width * height` entries.
    pub pixels: Vec<[f32; 3]>,
}

impl Rgb32Image {
    /// A black image of the given size.
    pub fn new(width: u32, height: u32) -> Self {
        Self::from_fn(width, height, |_, _| [0.0; 3])
    }

    /// An image whose pixel `(x, y)` is `f(x, y)`.
    pub fn from_fn(width: u32, height: u32, mut f: impl FnMut(u32, u32) -> [f32; 3]) -> Self {
        let pixels = (0..height).flat_map(|y| (0..width).map(move |x| (x, y))).map(|(x, y)| f(x, y)).collect();
        Self { width, height, pixels }
    }

    /// The RGB of `rgba` texels, row by row from the top (alpha dropped). Panics unless
    /// there are `width * height` of them.
    pub fn from_rgba(width: u32, height: u32, rgba: &[[f32; 4]]) -> Self {
        assert_eq!(rgba.len(), width as usize * height as usize, "texel count");
        Self { width, height, pixels: rgba.iter().map(|&[r, g, b, _]| [r, g, b]).collect() }
    }

    /// Index of pixel `(x, y)` in `pixels`. Panics when out of bounds.
    fn index(&self, x: u32, y: u32) -> usize {
        assert!(x < self.width && y < self.height, "pixel ({x}, {y}) outside {}x{} image", self.width, self.height);
        y as usize * self.width as usize + x as usize
    }

    /// The pixel at `(x, y)`. Panics when out of bounds.
    pub fn get(&self, x: u32, y: u32) -> [f32; 3] {
        self.pixels[self.index(x, y)]
    }

    /// Sets the pixel at `(x, y)`. Panics when out of bounds.
    pub fn set(&mut self, x: u32, y: u32, value: [f32; 3]) {
        let i = self.index(x, y);
        self.pixels[i] = value;
    }

    /// Per-channel mean, accumulated in `f64`. NaN for an empty image.
    pub fn mean(&self) -> [f64; 3] {
        let mut sum = [0.0f64; 3];
        for p in &self.pixels {
            for c in 0..3 {
                sum[c] += f64::from(p[c]);
            }
        }
        let n = self.pixels.len() as f64;
        sum.map(|s| s / n)
    }

    /// Number of pixels `width * height` should hold.
    fn expected_len(&self) -> usize {
        self.width as usize * self.height as usize
    }
}

/// What went wrong in an [`ImageError`].
#[derive(Debug)]
pub enum ImageErrorKind {
    /// Opening, reading, writing or renaming the file failed.
    Io(io::Error),
    /// The EXR encoder or decoder failed (corrupt file, no RGB layer, ...).
    Exr(exr::error::Error),
    /// The PNG encoder or decoder failed.
    Png(image::ImageError),
    /// The path's extension is not one of [`SUPPORTED_EXTENSIONS`].
    UnsupportedExtension,
    /// The image's pixel buffer does not match its width and height.
    BadPixelBuffer {
        /// Pixels the buffer holds.
        len: usize,
        /// The image's width.
        width: u32,
        /// The image's height.
        height: u32,
    },
    /// The header claims more than [`MAX_PIXELS`] pixels.
    TooLarge {
        /// The width it claims.
        width: u64,
        /// The height it claims.
        height: u64,
    },
    /// The header claims more bytes of pixel data than the file holds.
    Truncated {
        /// Bytes the header's chunks and uncompressed samples take at least.
        claimed: u64,
        /// Bytes in the file.
        len: u64,
    },
}

/// An image could not be read or written; names the file and the cause.
#[derive(Debug)]
pub struct ImageError {
    path: PathBuf,
    kind: ImageErrorKind,
}

impl ImageError {
    fn new(path: &Path, kind: ImageErrorKind) -> Self {
        Self { path: path.to_path_buf(), kind }
    }

    /// The file being read or written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// What went wrong.
    pub fn kind(&self) -> &ImageErrorKind {
        &self.kind
    }
}

impl fmt::Display for ImageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let path = self.path.display();
        match &self.kind {
            ImageErrorKind::Io(e) => write!(f, "{path}: I/O error: {e}"),
            ImageErrorKind::Exr(e) => write!(f, "{path}: EXR error: {e}"),
            ImageErrorKind::Png(e) => write!(f, "{path}: PNG error: {e}"),
            ImageErrorKind::UnsupportedExtension => write!(
                f,
                "{path}: unsupported image extension; supported extensions are {}",
                SUPPORTED_EXTENSIONS.map(|e| format!(".{e}")).join(", ")
            ),
            ImageErrorKind::BadPixelBuffer { len, width, height } => {
                write!(f, "{path}: image has {len} pixels but {width}x{height} needs {}", *width as usize * *height as usize)
            }
            ImageErrorKind::TooLarge { width, height } => write!(
                f,
                "{path}: the header claims a {width}x{height} image, more than the {MAX_PIXELS} pixels (16384x16384) \
                 an image may have here"
            ),
            ImageErrorKind::Truncated { claimed, len } => write!(
                f,
                "{path}: the header claims at least {claimed} bytes of pixel data but the file holds {len}: truncated or corrupt"
            ),
        }
    }
}

impl std::error::Error for ImageError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.kind {
            ImageErrorKind::Io(e) => Some(e),
            ImageErrorKind::Exr(e) => Some(e),
            ImageErrorKind::Png(e) => Some(e),
            ImageErrorKind::UnsupportedExtension
            | ImageErrorKind::BadPixelBuffer { .. }
            | ImageErrorKind::TooLarge { .. }
            | ImageErrorKind::Truncated { .. } => None,
        }
    }
}

/// File extensions understood by [`read_image`] and [`write_image`]
/// (matched case-insensitively).
pub const SUPPORTED_EXTENSIONS: [&str; 2] = ["png", "exr"];

/// Image file formats, chosen by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Png,
    Exr,
}

impl Format {
    /// The format named by `path`'s extension, case-insensitively.
    fn from_path(path: &Path) -> Result<Self, ImageError> {
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("png") => Ok(Format::Png),
            Some("exr") => Ok(Format::Exr),
            _ => Err(ImageError::new(path, ImageErrorKind::UnsupportedExtension)),
        }
    }
}

/// sRGB opto-electronic transfer function (linear → encoded), exact piecewise
/// form. Not clamped.
pub fn linear_to_srgb(x: f32) -> f32 {
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// Inverse of [`linear_to_srgb`] (encoded → linear). Not clamped.
pub fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear value to an 8-bit sRGB code: OETF, clamp to `[0, 1]`, round.
/// NaN maps to 0 and +inf to 255.
fn linear_to_srgb8(x: f32) -> u8 {
    let v = linear_to_srgb(x);
    if v.is_nan() {
        0
    } else {
        (v.clamp(0.0, 1.0) * 255.0).round() as u8
    }
}

/// Writes `img` as an 8-bit sRGB PNG (see [`linear_to_srgb`]).
pub fn write_png(path: &Path, img: &Rgb32Image) -> Result<(), ImageError> {
    check_pixel_buffer(path, img)?;
    let bytes: Vec<u8> = img.pixels.iter().flatten().map(|&x| linear_to_srgb8(x)).collect();
    let mut encoded = Vec::new();
    image::codecs::png::PngEncoder::new(&mut encoded)
        .write_image(&bytes, img.width, img.height, ExtendedColorType::Rgb8)
        .map_err(|e| ImageError::new(path, ImageErrorKind::Png(e)))?;
    write_atomically(path, &encoded)
}

/// Writes `img` as a linear float32 RGB OpenEXR file (no alpha).
pub fn write_exr(path: &Path, img: &Rgb32Image) -> Result<(), ImageError> {
    write_exr_with_text(path, img, &[])
}

/// [`write_exr`] with text attributes in the header, `(name, value)`: Latin-1 text each
/// (the renderer's partial images carry their pass range and fingerprint this way).
pub fn write_exr_with_text(path: &Path, img: &Rgb32Image, text: &[(&str, &str)]) -> Result<(), ImageError> {
    write_exr_with_channels(path, img, &[], text)
}

/// [`write_exr_with_text`] with more f32 channels beside R, G and B, each `(name, plane)`: a
/// plane of `width * height` values, row-major (a partial image's splat weights).
pub fn write_exr_with_channels(
    path: &Path,
    img: &Rgb32Image,
    extra: &[(&str, &[f32])],
    text: &[(&str, &str)],
) -> Result<(), ImageError> {
    check_pixel_buffer(path, img)?;
    let latin1 = |s: &str| {
        exr::prelude::Text::new_or_none(s).ok_or_else(|| {
            let message = format!("the header text or channel name `{s}` is not Latin-1");
            ImageError::new(path, ImageErrorKind::Exr(exr::error::Error::Invalid(message.into())))
        })
    };
    let size = (img.width as usize, img.height as usize);
    let mut encoded = Vec::new();
    let mut attributes = exr::meta::header::LayerAttributes::default();
    for (name, value) in text {
        attributes.other.insert(latin1(name)?, exr::meta::attribute::AttributeValue::Text(latin1(value)?));
    }
    let write = |result: exr::error::UnitResult| result.map_err(|e| ImageError::new(path, ImageErrorKind::Exr(e)));
    if extra.is_empty() {
        let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
            let [r, g, b] = img.pixels[y * img.width as usize + x];
            (r, g, b)
        });
        let mut image = exr::prelude::Image::from_channels(size, channels);
        image.layer_data.attributes = attributes;
        write(image.write().to_buffered(Cursor::new(&mut encoded)))?;
    } else {
        use exr::prelude::{AnyChannel, AnyChannels, FlatSamples};
        let plane = |c: usize| FlatSamples::F32(img.pixels.iter().map(|p| p[c]).collect());
        let mut list: exr::prelude::SmallVec<[AnyChannel<FlatSamples>; 4]> =
            ["R", "G", "B"].iter().enumerate().map(|(c, name)| AnyChannel::new(*name, plane(c))).collect();
        for (name, values) in extra {
            if values.len() != img.pixels.len() {
                let message = format!("channel `{name}` holds {} values for {} pixels", values.len(), img.pixels.len());
                return Err(ImageError::new(path, ImageErrorKind::Exr(exr::error::Error::Invalid(message.into()))));
            }
            list.push(AnyChannel::new(latin1(name)?, FlatSamples::F32(values.to_vec())));
        }
        let layer = exr::prelude::Layer::new(size, attributes, exr::prelude::Encoding::FAST_LOSSLESS, AnyChannels::sort(list));
        write(exr::prelude::Image::from_layer(layer).write().to_buffered(Cursor::new(&mut encoded)))?;
    }
    write_atomically(path, &encoded)
}

/// The f32 planes (row-major) of the channels `names` of an EXR's first layer, `None` for a
/// name it lacks (f16 and u32 channels converted), its size, and its text attributes as
/// [`read_exr_with_text`] gives them: one read for all of a partial image.
pub fn read_exr_channels(path: &Path, names: &[&str]) -> Result<ExrChannels, ImageError> {
    let mut file = File::open(path).map_err(|e| ImageError::new(path, ImageErrorKind::Io(e)))?;
    check_exr_header(path, &mut file)?;
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_unbuffered(file)
        .map_err(|e| ImageError::new(path, ImageErrorKind::Exr(e)))?;
    let channels = &image.layer_data.channel_data.list;
    let planes = names
        .iter()
        .map(|name| {
            channels.iter().find(|c| c.name.to_string() == *name).map(|c| match &c.sample_data {
                exr::prelude::FlatSamples::F32(v) => v.clone(),
                exr::prelude::FlatSamples::F16(v) => v.iter().map(|h| h.to_f32()).collect(),
                exr::prelude::FlatSamples::U32(v) => v.iter().map(|&u| u as f32).collect(),
            })
        })
        .collect();
    let Vec2(width, height) = image.layer_data.size;
    let text = text_attributes(&image.layer_data.attributes, &image.attributes);
    Ok(ExrChannels { planes, width: width as u32, height: height as u32, text })
}

/// What [`read_exr_channels`] read.
pub struct ExrChannels {
    /// The planes asked for, in order; `None` where the file lacks the channel.
    pub planes: Vec<Option<Vec<f32>>>,
    /// The layer's width.
    pub width: u32,
    /// The layer's height.
    pub height: u32,
    /// The header's text attributes, `(name, value)`.
    pub text: Vec<(String, String)>,
}

/// Writes `img` in the format named by `path`'s extension (`.png` or `.exr`,
/// case-insensitive); any other extension is an error.
pub fn write_image(path: &Path, img: &Rgb32Image) -> Result<(), ImageError> {
    match Format::from_path(path)? {
        Format::Png => write_png(path, img),
        Format::Exr => write_exr(path, img),
    }
}

/// Reads the first layer with `R`, `G` and `B` channels of an OpenEXR file.
///
/// Channels may appear in any order and be f16, f32 or u32; other channels are
/// ignored. Row 0 is the top of the data window.
pub fn read_exr(path: &Path) -> Result<Rgb32Image, ImageError> {
    Ok(read_exr_with_text(path)?.0)
}

/// [`read_exr`], and the header's text attributes, `(name, value)`.
pub fn read_exr_with_text(path: &Path) -> Result<(Rgb32Image, Vec<(String, String)>), ImageError> {
    let mut file = File::open(path).map_err(|e| ImageError::new(path, ImageErrorKind::Io(e)))?;
    check_exr_header(path, &mut file)?;
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |Vec2(w, h), _| Rgb32Image::new(w as u32, h as u32),
            |img: &mut Rgb32Image, Vec2(x, y), (r, g, b): (f32, f32, f32)| img.set(x as u32, y as u32, [r, g, b]),
        )
        .first_valid_layer()
        .all_attributes()
        .from_unbuffered(file)
        .map_err(|e| ImageError::new(path, ImageErrorKind::Exr(e)))?;
    let text = text_attributes(&image.layer_data.attributes, &image.attributes);
    Ok((image.layer_data.channel_data.pixels, text))
}

/// The text attributes of an EXR's layer and image, `(name, value)` (the reader files unknown
/// attributes under the layer).
fn text_attributes(
    layer: &exr::meta::header::LayerAttributes,
    image: &exr::meta::header::ImageAttributes,
) -> Vec<(String, String)> {
    layer
        .other
        .iter()
        .chain(&image.other)
        .filter_map(|(key, value)| match value {
            exr::meta::attribute::AttributeValue::Text(t) => Some((key.to_string(), t.to_string())),
            _ => None,
        })
        .collect()
}

/// Refuses the EXR `file` (at `path`) when a layer's header claims more than [`MAX_PIXELS`]
/// pixels, or more bytes than the file holds: each chunk takes 16 at least (its offset and
/// its header), and an uncompressed layer all its samples. Leaves `file` at its start.
fn check_exr_header(path: &Path, file: &mut File) -> Result<(), ImageError> {
    let io_error = |e| ImageError::new(path, ImageErrorKind::Io(e));
    let len = file.metadata().map_err(io_error)?.len();
    let meta = exr::meta::MetaData::read_from_unbuffered(&mut *file, false)
        .map_err(|e| ImageError::new(path, ImageErrorKind::Exr(e)))?;
    let mut claimed = 0u64;
    for header in &meta.headers {
        let Vec2(width, height) = header.layer_size;
        check_size(path, width as u64, height as u64)?;
        claimed = claimed.saturating_add(16u64.saturating_mul(header.chunk_count as u64));
        if header.compression == Compression::Uncompressed && !header.deep {
            let samples = width as u64 * height as u64 * header.channels.bytes_per_pixel as u64;
            claimed = claimed.saturating_add(samples);
        }
    }
    if claimed > len {
        return Err(ImageError::new(path, ImageErrorKind::Truncated { claimed, len }));
    }
    file.seek(SeekFrom::Start(0)).map(drop).map_err(io_error)
}

/// Errors unless a `width` x `height` image has at most [`MAX_PIXELS`] pixels.
fn check_size(path: &Path, width: u64, height: u64) -> Result<(), ImageError> {
    if width.saturating_mul(height) > MAX_PIXELS {
        Err(ImageError::new(path, ImageErrorKind::TooLarge { width, height }))
    } else {
        Ok(())
    }
}

/// Reads a PNG, decoding sRGB to linear. Alpha is dropped; 16-bit and
/// grey-scale PNGs are accepted.
pub fn read_png(path: &Path) -> Result<Rgb32Image, ImageError> {
    let bytes = fs::read(path).map_err(|e| ImageError::new(path, ImageErrorKind::Io(e)))?;
    let png_error = |e| ImageError::new(path, ImageErrorKind::Png(e));
    let reader = || image::ImageReader::with_format(Cursor::new(&bytes), ImageFormat::Png);
    let (width, height) = reader().into_dimensions().map_err(png_error)?;
    check_size(path, width.into(), height.into())?;
    let mut reader = reader();
    let mut limits = image::Limits::default();
    // The decoder's buffer: 8 bytes a pixel at most (16-bit RGBA).
    limits.max_alloc = Some(MAX_PIXELS * 8);
    reader.limits(limits);
    let decoded = reader.decode().map_err(png_error)?.into_rgb32f();
    let pixels = decoded.pixels().map(|p| p.0.map(srgb_to_linear)).collect();
    Ok(Rgb32Image { width: decoded.width(), height: decoded.height(), pixels })
}

/// Reads an image in the format named by `path`'s extension (`.png` or
/// `.exr`, case-insensitive); any other extension is an error.
pub fn read_image(path: &Path) -> Result<Rgb32Image, ImageError> {
    match Format::from_path(path)? {
        Format::Png => read_png(path),
        Format::Exr => read_exr(path),
    }
}

/// Errors unless `img.pixels` holds exactly `width * height` pixels.
fn check_pixel_buffer(path: &Path, img: &Rgb32Image) -> Result<(), ImageError> {
    if img.pixels.len() == img.expected_len() {
        Ok(())
    } else {
        let kind = ImageErrorKind::BadPixelBuffer { len: img.pixels.len(), width: img.width, height: img.height };
        Err(ImageError::new(path, kind))
    }
}

/// Writes `bytes` to `path` via a temporary file `.<name>.tmp-<pid>-<n>` in the
/// same directory, renamed over `path` once complete. The temporary file is
/// removed if anything fails.
fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), ImageError> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let io_error = |e| ImageError::new(path, ImageErrorKind::Io(e));
    let name = path.file_name().ok_or_else(|| io_error(io::Error::new(io::ErrorKind::InvalidInput, "path has no file name")))?;
    let mut tmp_name = OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(format!(".tmp-{}-{}", std::process::id(), COUNTER.fetch_add(1, Ordering::Relaxed)));
    let tmp = path.with_file_name(tmp_name);

    let result = File::create(&tmp)
        .and_then(|mut file| {
            file.write_all(bytes)?;
            file.sync_all()
        })
        .and_then(|()| fs::rename(&tmp, path));
    if result.is_err() {
        // Best effort: the temporary file may not exist, and the original
        // error is the one worth reporting.
        let _ = fs::remove_file(&tmp);
    }
    result.map_err(io_error)
}
