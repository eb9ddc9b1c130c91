//! Mitsuba 3's texture plugins, as our [`Texture`]s (its plugin reference, "Textures"). A
//! texture stands for a reflectance: nested in a BSDF under the parameter's name, or declared
//! at the top level with an `id` and named by `<ref name=".." id=".."/>`. Every texture is
//! looked up at (x, y) = `to_uv` * uv, x right and y down the image, with the shape's uv in
//! Mitsuba's convention (see shape.rs):
//!
//! - `bitmap`: `filename` (required; PNG, JPEG, OpenEXR, Radiance HDR), `raw` (false: an 8- or
//!   16-bit image is sRGB-decoded, a floating-point one is linear, as Mitsuba 3's `Bitmap`
//!   flags them; true: values as stored), `filter_type` (`bilinear`, the default, with texel
//!   centres at half-integers, or `nearest`), `wrap_mode` (`repeat`, the default, `mirror`,
//!   `clamp`), `to_uv` (identity), `format` (`auto`; a storage precision, which changes values
//!   by at most half precision's rounding; `uint8`, which would quantize float images, is
//!   refused), `accel` (true; hardware interpolation on CUDA, no effect here).
//! - `checkerboard`: `color0` (0.4) and `color1` (0.2), each a colour, and `to_uv`: color0
//!   where the fractional parts of x and y are both above 1/2 or both not, color1 elsewhere.
//!   It becomes a 2x2 texture sampled nearest with repeat, which switches colour at the same
//!   x and y (at exactly 1/2 Mitsuba's test `> 1/2` keeps the lower colour, the texel the
//!   upper: a set of no area).
//!
//! In a 0.x scene, Mitsuba 0.6's parameters too. Of every texture: `uscale`, `vscale` (each
//! `uvscale`, 1), `uoffset`, `voffset` (0), its uv times the scales plus the offsets, after
//! `to_uv`; `coordinates` (`uv`, the only kind). Of `bitmap`: `gamma`
//! ([`Props::legacy_gamma`]); `wrap_mode_u` and `wrap_mode_v` (each `wrap_mode`), the same
//! or refused, as ours wraps both alike; `filter_type` `ewa` and `trilinear` (filtering over
//! a pixel's footprint, which the pixel's samples also average) read as `bilinear` with a
//! warning, and `max_anisotropy` (EWA's) and `cache` (whether Mitsuba 0.6 keeps its MIP map
//! in a file) warned; `channel` (one channel of the image, as grey) refused.

use super::props::{Props, Spectrum};
use super::xml::Node;
use super::{Result, SceneReader};
use crate::scene::{mesh, Texture, TextureFilter, TextureWrap};
use glam::{Affine2, Mat2, Vec2, Vec3};

impl<'a> SceneReader<'a> {
    /// The index in the scene's textures of texture element `node` (or the one a `<ref>`
    /// names), read once however many BSDFs refer to it.
    pub(super) fn texture(&mut self, node: &'a Node) -> Result<u32> {
        let node = self.deref(node, "texture")?;
        if let Some(&index) = self.texture_of.get(&(node as *const Node)) {
            return Ok(index);
        }
        node.allow_attrs(&["type", "id", "name"])?;
        let kind = node.req_attr("type")?;
        let p = Props::new(node)?;
        let texture = match kind {
            "bitmap" => self.bitmap(&p)?,
            "checkerboard" => checkerboard(&p)?,
            "mesh_attribute" | "volume" | "spectrum" => {
                return Err(node.error(Some("type"), format!("the `{kind}` texture is not modelled by sppm-gpu")))
            }
            other => return Err(node.error(Some("type"), format!("`{other}` is not a Mitsuba 3 texture plugin"))),
        };
        p.finish()?;
        let index = self.textures.len() as u32;
        self.textures.push(texture);
        self.texture_of.insert(node as *const Node, index);
        Ok(index)
    }

    /// A `bitmap` texture's image and sampling.
    fn bitmap(&self, p: &Props<'a>) -> Result<Texture> {
        let name = p.string("filename")?.ok_or_else(|| p.node.error(Some("filename"), "a bitmap texture needs a `filename`"))?;
        let path = super::xml::resolve(name, &p.node.file, &self.root);
        let raw = p.boolean_or("raw", false)?;
        let raw = p.legacy_gamma(&path)?.unwrap_or(raw);
        let filter = match p.string("filter_type")?.map(str::trim).unwrap_or("bilinear") {
            "bilinear" => TextureFilter::Bilinear,
            "nearest" => TextureFilter::Nearest,
            other @ ("ewa" | "trilinear") if p.node.legacy() => {
                p.get("filter_type").unwrap().warn(
                    Some("filter_type"),
                    format!(
                        "filter_type \"{other}\" is read as bilinear: Mitsuba 0.6 filters over the pixel's footprint, \
                         which the pixel's samples average here"
                    ),
                );
                TextureFilter::Bilinear
            }
            other => {
                let at = p.get("filter_type").unwrap();
                return Err(at.error(Some("filter_type"), format!("filter_type \"{other}\" is not one of bilinear, nearest")));
            }
        };
        let wrap_mode = |name: &str, default: &str| -> Result<TextureWrap> {
            match p.string(name)?.map(str::trim).unwrap_or(default) {
                "repeat" => Ok(TextureWrap::Repeat),
                "mirror" => Ok(TextureWrap::Mirror),
                "clamp" => Ok(TextureWrap::Clamp),
                other => {
                    let at = p.get(name).unwrap();
                    Err(at.error(Some(name), format!("{name} \"{other}\" is not one of repeat, mirror, clamp")))
                }
            }
        };
        let mut wrap = wrap_mode("wrap_mode", "repeat")?;
        if p.node.legacy() {
            // Mitsuba 0.6 wraps u and v each its own way, by default wrap_mode's.
            let u = if p.has("wrap_mode_u") { wrap_mode("wrap_mode_u", "repeat")? } else { wrap };
            let v = if p.has("wrap_mode_v") { wrap_mode("wrap_mode_v", "repeat")? } else { wrap };
            if u != v {
                let key = if p.has("wrap_mode_v") { "wrap_mode_v" } else { "wrap_mode_u" };
                let name = |w: TextureWrap| format!("{w:?}").to_lowercase();
                return Err(p
                    .get(key)
                    .unwrap()
                    .error(Some(key), format!("u wraps by {}, v by {}: sppm-gpu wraps u and v alike", name(u), name(v))));
            }
            wrap = u;
            if let Some(channel) = p.string("channel")?.filter(|c| !c.trim().is_empty()) {
                let at = p.get("channel").unwrap();
                return Err(at.error(
                    Some("channel"),
                    format!("channel \"{channel}\" (one channel of the image) is not modelled by sppm-gpu"),
                ));
            }
            p.legacy_ignored(&["max_anisotropy"], "it bounds Mitsuba 0.6's EWA filtering, read as bilinear here");
            p.legacy_ignored(
                &["cache"],
                "it says whether Mitsuba 0.6 keeps the texture's MIP map in a file, which changes the speed",
            );
        }
        match p.string("format")?.map(str::trim).unwrap_or("auto") {
            "auto" | "variant" | "float16" | "fp16" => {}
            "uint8" => {
                let at = p.get("format").unwrap();
                return Err(at.error(Some("format"), "format \"uint8\" (8-bit storage of any image) is not modelled by sppm-gpu"));
            }
            other => {
                let at = p.get("format").unwrap();
                return Err(at.error(Some("format"), format!("format \"{other}\" is not one of auto, variant, float16, uint8")));
            }
        }
        p.boolean_or("accel", true)?;
        let to_uv = to_uv(p)?;
        let at = p.get("filename").unwrap();
        let mut texture =
            mesh::read_image(&path, raw).map_err(|e| at.error(Some("filename"), format!("{}: {e}", path.display())))?;
        if texture.width == 0 || texture.height == 0 {
            return Err(at.error(Some("filename"), format!("{}: the image has no texels", path.display())));
        }
        texture.filter = filter;
        texture.wrap = wrap;
        texture.to_uv = to_uv;
        Ok(texture)
    }
}

/// A `checkerboard` texture as a 2x2 texture, sampled nearest with repeat: texel column i
/// covers x in [i/2, (i+1)/2) of each unit tile, row j likewise in y, and color0 lies where
/// i == j.
fn checkerboard(p: &Props) -> Result<Texture> {
    let color = |name: &str, default: f32| -> Result<Vec3> {
        match p.spectrum(name)? {
            None => Ok(Vec3::splat(default)),
            Some(Spectrum::Rgb(rgb)) => Ok(rgb),
            Some(Spectrum::Texture(node)) => Err(node
                .error(Some(name), format!("a checkerboard's {name} as a texture is not modelled by sppm-gpu: give a colour"))),
        }
    };
    let (color0, color1) = (color("color0", 0.4)?, color("color1", 0.2)?);
    let to_uv = to_uv(p)?;
    Ok(Texture {
        path: p.node.file.as_ref().clone(),
        width: 2,
        height: 2,
        texels: std::sync::Arc::new(vec![color0, color1, color1, color0]),
        filter: TextureFilter::Nearest,
        wrap: TextureWrap::Repeat,
        to_uv,
    })
}

/// A texture's `to_uv`: a `<transform>` read as Mitsuba's 3x3 affine map of (u, v, 1), the
/// 4x4 matrix's upper-left 2x2 block and the first two entries of its translation (Mitsuba's
/// `Transform4f::extract`); identity when left out. In a 0.x scene followed by Mitsuba 0.6's
/// scales and offsets of uv.
fn to_uv(p: &Props) -> Result<Affine2> {
    let to_uv = match p.transform("to_uv")? {
        Some(m) => Affine2::from_mat2_translation(
            Mat2::from_cols(m.x_axis.truncate().truncate(), m.y_axis.truncate().truncate()),
            Vec2::new(m.w_axis.x, m.w_axis.y),
        ),
        None => Affine2::IDENTITY,
    };
    if !p.node.legacy() {
        return Ok(to_uv);
    }
    match p.string("coordinates")?.map(str::trim) {
        None | Some("uv") => {}
        Some(other) => {
            let at = p.get("coordinates").unwrap();
            return Err(at.error(Some("coordinates"), format!("coordinates \"{other}\": textures are looked up by uv")));
        }
    }
    let uvscale = p.float_or("uvscale", 1.0)?;
    let scale = Vec2::new(p.float_or("uscale", uvscale)?, p.float_or("vscale", uvscale)?);
    let offset = Vec2::new(p.float_or("uoffset", 0.0)?, p.float_or("voffset", 0.0)?);
    Ok(Affine2::from_scale_angle_translation(scale, 0.0, offset) * to_uv)
}
