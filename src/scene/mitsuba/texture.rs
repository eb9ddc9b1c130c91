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

use super::props::{Props, Spectrum};
use super::xml::Node;
use super::{Result, SceneReader};
use crate::scene::{mesh, Texture, TextureFilter, TextureWrap};
use glam::{Affine2, Mat2, Mat4, Vec2, Vec3};

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
        let filter = match p.string("filter_type")?.map(str::trim).unwrap_or("bilinear") {
            "bilinear" => TextureFilter::Bilinear,
            "nearest" => TextureFilter::Nearest,
            other => {
                let at = p.get("filter_type").unwrap();
                return Err(at.error(Some("filter_type"), format!("filter_type \"{other}\" is not one of bilinear, nearest")));
            }
        };
        let wrap = match p.string("wrap_mode")?.map(str::trim).unwrap_or("repeat") {
            "repeat" => TextureWrap::Repeat,
            "mirror" => TextureWrap::Mirror,
            "clamp" => TextureWrap::Clamp,
            other => {
                let at = p.get("wrap_mode").unwrap();
                return Err(at.error(Some("wrap_mode"), format!("wrap_mode \"{other}\" is not one of repeat, mirror, clamp")));
            }
        };
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
        texels: vec![color0, color1, color1, color0],
        filter: TextureFilter::Nearest,
        wrap: TextureWrap::Repeat,
        to_uv,
    })
}

/// A texture's `to_uv`: a `<transform>` read as Mitsuba's 3x3 affine map of (u, v, 1), the
/// 4x4 matrix's upper-left 2x2 block and the first two entries of its translation (Mitsuba's
/// `Transform4f::extract`); identity when left out.
fn to_uv(p: &Props) -> Result<Affine2> {
    let Some(m): Option<Mat4> = p.transform("to_uv")? else { return Ok(Affine2::IDENTITY) };
    Ok(Affine2::from_mat2_translation(
        Mat2::from_cols(m.x_axis.truncate().truncate(), m.y_axis.truncate().truncate()),
        Vec2::new(m.w_axis.x, m.w_axis.y),
    ))
}
