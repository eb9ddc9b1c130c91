//! pbrt-v4's scene files (`.pbrt`), read into the same [`Scene`] as our TOML and Mitsuba's XML,
//! as pbrt-v4 reads them (its file format reference, pbrt.org/fileformat-v4). What cannot be
//! rendered here is refused before any work, with the file, line and directive or parameter;
//! what pbrt-v4 reads but that changes only the noise or the speed here is passed over, with a
//! warning where it would change pbrt-v4's image. A parameter a directive does not take is an
//! error, as in pbrt-v4 ("unused parameter").
//!
//! - `lexer.rs`: tokens; `params.rs`: typed parameter lists; `spectra.rs`: spectra to RGB.
//! - This file: the directives. `Include` and `Import` (file names relative to the main scene
//!   file's directory, as pbrt-v4 resolves them, else to the including file's); the
//!   transforms `Identity`, `Translate`, `Scale`, `Rotate`, `LookAt`, `Transform`,
//!   `ConcatTransform`, `CoordinateSystem`, `CoordSysTransform` (`camera`, `world` and named
//!   ones); `ReverseOrientation`; `AttributeBegin`/`AttributeEnd` and the deprecated
//!   `TransformBegin`/`TransformEnd` (warned, as pbrt-v4 warns); `ObjectBegin`/`ObjectEnd`/
//!   `ObjectInstance` (instances are copied); `WorldBegin`; `MakeNamedMaterial`,
//!   `NamedMaterial`, `Material`, `Texture` (material.rs); `LightSource`, `AreaLightSource`
//!   (light.rs); `Shape` (shape.rs); `Camera`, `Film`, `PixelFilter`, `Sampler`,
//!   `Integrator` (camera.rs); `Accelerator` (the speed: passed over), `ColorSpace` (`srgb`
//!   only), `Option` (warned); `MakeNamedMedium` and `MediumInterface` (medium.rs).
//!   `Attribute` is refused. `loopsubdiv` is subdivided in subdiv.rs.
//!
//! Handedness: pbrt's camera space is left-handed, its raster x running along camera +x; ours
//! is right-handed. Where the camera's transform does not mirror (a plain `LookAt`), pbrt's
//! image is the mirror of what our camera would see, so the world is mirrored across the
//! plane of the camera's view and up directions (through the camera): the same image.

mod camera;
mod lexer;
mod light;
mod material;
mod medium;
mod params;
mod shape;
mod spectra;
mod subdiv;

use super::mesh::PrimitiveBudget;
use super::{Light, Material, Medium, Scene, SceneError, Shape, Sphere, Texture, Triangle};
use glam::{Mat4, Vec3};
use lexer::{Tok, Token};
use params::Params;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;

type Result<T> = std::result::Result<T, SceneError>;

/// Deepest nesting of `Include`s (a file that includes itself is refused by it).
const MAX_INCLUDE_DEPTH: usize = 32;

/// Reads pbrt-v4 scene file `path`, printing its warnings (to stderr).
pub fn load(path: &Path) -> Result<Scene> {
    let (scene, warnings) = load_with_warnings(path);
    for warning in &warnings {
        eprintln!("warning: {warning}");
    }
    scene
}

/// Reads pbrt-v4 scene file `path` as [`load`] does, giving back its warnings, each with the
/// file, line and directive or parameter it is about, rather than printing them.
pub fn load_with_warnings(path: &Path) -> (Result<Scene>, Vec<SceneError>) {
    let mut reader = Reader::new(path);
    let scene = reader.include(path, None, 0).and_then(|()| reader.finish());
    (scene, std::mem::take(&mut reader.warnings))
}

/// Reads pbrt-v4 scene text as if it were the file `path` (for tests and fuzzing: includes
/// and other files resolve against `path`'s directory).
pub fn load_str(text: &str, path: &Path) -> (Result<Scene>, Vec<SceneError>) {
    let mut reader = Reader::new(path);
    let file = Rc::new(path.to_path_buf());
    let scene = lexer::tokenize(text, path).and_then(|t| reader.run(&t, &file, 0)).and_then(|()| reader.finish());
    (scene, std::mem::take(&mut reader.warnings))
}

/// An area light's emission, for the shapes that follow it.
#[derive(Clone, Debug)]
struct AreaLight {
    /// `L` times `scale`.
    radiance: Vec3,
    /// `power`, where given and positive: the radiance of each pbrt shape is scaled by power
    /// / (pi area) (shape.rs).
    power: Option<f32>,
    /// `twosided`: the radiance leaves both sides of each shape.
    two_sided: bool,
}

/// The attributes `AttributeBegin` saves.
#[derive(Clone, Debug)]
struct State {
    /// The CTM at the start time of `TransformTimes` ...
    ctm: Mat4,
    /// ... and at its end time: they differ where `ActiveTransform` set one alone (motion).
    ctm_end: Mat4,
    /// Which of the two the transform directives set (`ActiveTransform`): start, end.
    active: [bool; 2],
    reverse: bool,
    /// Index into the materials; `None` for pbrt-v4's default (a diffuse of 0.5).
    material: Option<u32>,
    area: Option<AreaLight>,
    /// `MediumInterface`: the media inside and outside the shapes that follow ("" for none).
    media: (String, String),
}

/// What a `*Begin` pushed.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Block {
    Attribute,
    Transform,
    Object,
}

/// A shape inside `ObjectBegin`/`ObjectEnd`, made once for each `ObjectInstance`.
#[derive(Clone, Debug)]
struct ShapeRecord {
    kind: String,
    params: Params,
    ctm: Mat4,
    reverse: bool,
    material: Option<u32>,
    media: (String, String),
}

/// The scene-wide options given before `WorldBegin`: each directive's type and parameters.
#[derive(Default)]
struct Options {
    camera: Option<(String, Params, Mat4)>,
    film: Option<(String, Params)>,
    filter: Option<(String, Params)>,
    sampler: Option<(String, Params)>,
    integrator: Option<(String, Params)>,
}

/// The scene as it is being read.
struct Reader {
    path: PathBuf,
    /// The main file's directory, where pbrt-v4 resolves file names.
    dir: Rc<PathBuf>,
    warnings: Vec<SceneError>,
    state: State,
    stack: Vec<(State, Block, Rc<PathBuf>, usize)>,
    /// `CoordinateSystem`'s CTMs, at the start and end times.
    named_coords: HashMap<String, [Mat4; 2]>,
    /// `TransformTimes` (0, 1).
    transform_times: (f32, f32),
    world: bool,
    /// The mirror of the world our camera needs (identity when none, and before `WorldBegin`).
    mirror: Mat4,
    options: Options,
    materials: Vec<Material>,
    named_materials: HashMap<String, u32>,
    default_material: Option<u32>,
    textures: Vec<Texture>,
    float_textures: HashMap<String, material::FloatTexture>,
    spectrum_textures: HashMap<String, material::SpectrumTexture>,
    /// The scene texture of each image texture name, made once.
    texture_index: HashMap<String, u32>,
    shapes: Vec<Shape>,
    triangles: Vec<Triangle>,
    spheres: Vec<Sphere>,
    lights: Vec<Light>,
    objects: HashMap<String, Vec<ShapeRecord>>,
    /// The object being defined, and its shapes.
    object: Option<(String, Vec<ShapeRecord>)>,
    budget: PrimitiveBudget,
    media: Vec<Medium>,
    named_media: HashMap<String, u32>,
    /// Shapes whose `MediumInterface` names media, resolved at the end (pbrt-v4 looks names
    /// up once the whole file is read): the shape, its (inside, outside) media, and the error
    /// that names the shape's directive.
    shape_media: Vec<(u32, (String, String), SceneError)>,
    /// The camera's medium: the outside medium of the `MediumInterface` in force at `Camera`.
    camera_medium: Option<(String, SceneError)>,
}

impl Reader {
    fn new(path: &Path) -> Self {
        Reader {
            path: path.to_path_buf(),
            dir: Rc::new(path.parent().unwrap_or(Path::new("")).to_path_buf()),
            warnings: Vec::new(),
            state: State {
                ctm: Mat4::IDENTITY,
                ctm_end: Mat4::IDENTITY,
                active: [true; 2],
                reverse: false,
                material: None,
                area: None,
                media: Default::default(),
            },
            stack: Vec::new(),
            named_coords: HashMap::new(),
            transform_times: (0.0, 1.0),
            world: false,
            mirror: Mat4::IDENTITY,
            options: Options::default(),
            materials: Vec::new(),
            named_materials: HashMap::new(),
            default_material: None,
            textures: Vec::new(),
            float_textures: HashMap::new(),
            spectrum_textures: HashMap::new(),
            texture_index: HashMap::new(),
            shapes: Vec::new(),
            triangles: Vec::new(),
            spheres: Vec::new(),
            lights: Vec::new(),
            objects: HashMap::new(),
            object: None,
            budget: PrimitiveBudget::new(),
            media: Vec::new(),
            named_media: HashMap::new(),
            shape_media: Vec::new(),
            camera_medium: None,
        }
    }

    /// Reads file `path` (named at `at`, the including file and line, for messages).
    fn include(&mut self, path: &Path, at: Option<(&Rc<PathBuf>, usize)>, depth: usize) -> Result<()> {
        let err = |m: String| match at {
            Some((file, line)) => SceneError::new(file, Some(line), Some("Include"), m),
            None => SceneError::new(path, None, None, m),
        };
        if depth > MAX_INCLUDE_DEPTH {
            return Err(err(format!("Includes nest more than {MAX_INCLUDE_DEPTH} deep (a file that includes itself?)")));
        }
        let text = super::files::read_text(path).map_err(|e| err(format!("{}: {e}", path.display())))?;
        let tokens = lexer::tokenize(&text, path)?;
        self.run(&tokens, &Rc::new(path.to_path_buf()), depth)
    }

    /// Runs the directives of `tokens`, read from `file`.
    fn run(&mut self, tokens: &[Token], file: &Rc<PathBuf>, depth: usize) -> Result<()> {
        let mut i = 0;
        while i < tokens.len() {
            let line = tokens[i].line;
            let name = match &tokens[i].tok {
                Tok::Word(w) => w.clone(),
                _ => {
                    return Err(SceneError::new(
                        file,
                        Some(line),
                        None,
                        format!("{}: expected a directive (Shape, LookAt, ...)", tokens[i].describe()),
                    ))
                }
            };
            i += 1;
            let err = |m: String| SceneError::new(file, Some(line), Some(&name), m);
            let mut args = Args { tokens, i: &mut i, file, line, name: &name };
            match name.as_str() {
                "Identity" => self.set_ctm(Mat4::IDENTITY),
                "Translate" => {
                    let v = args.numbers(3)?;
                    self.concat(Mat4::from_translation(Vec3::new(v[0], v[1], v[2])));
                }
                "Scale" => {
                    let v = args.numbers(3)?;
                    self.concat(Mat4::from_scale(Vec3::new(v[0], v[1], v[2])));
                }
                "Rotate" => {
                    let v = args.numbers(4)?;
                    let axis = Vec3::new(v[1], v[2], v[3]).normalize_or_zero();
                    if axis == Vec3::ZERO {
                        return Err(err("the rotation's axis is zero".into()));
                    }
                    self.concat(Mat4::from_axis_angle(axis, v[0].to_radians()));
                }
                "LookAt" => {
                    let v = args.numbers(9)?;
                    let m = look_at(Vec3::new(v[0], v[1], v[2]), Vec3::new(v[3], v[4], v[5]), Vec3::new(v[6], v[7], v[8]))
                        .map_err(err)?;
                    self.concat(m);
                }
                "Transform" | "ConcatTransform" => {
                    let v = args.matrix()?;
                    // The 16 numbers are the matrix's columns, as pbrt-v4 transposes them.
                    let m = Mat4::from_cols_array(&v);
                    if name == "Transform" {
                        self.set_ctm(m);
                    } else {
                        self.concat(m);
                    }
                }
                "CoordinateSystem" => {
                    let n = args.string()?;
                    self.named_coords.insert(n, [self.state.ctm, self.state.ctm_end]);
                }
                "CoordSysTransform" => {
                    let n = args.string()?;
                    match self.named_coords.get(&n) {
                        Some(&[start, end]) => (self.state.ctm, self.state.ctm_end) = (start, end),
                        None => self.warnings.push(err(format!("couldn't find named coordinate system \"{n}\""))),
                    }
                }
                "ReverseOrientation" => self.state.reverse = !self.state.reverse,
                "AttributeBegin" => self.stack.push((self.state.clone(), Block::Attribute, file.clone(), line)),
                "TransformBegin" => {
                    self.warnings.push(err("TransformBegin is deprecated and should be replaced with AttributeBegin".into()));
                    self.stack.push((self.state.clone(), Block::Transform, file.clone(), line));
                }
                "AttributeEnd" | "TransformEnd" => {
                    let want = if name == "AttributeEnd" { Block::Attribute } else { Block::Transform };
                    match self.stack.pop() {
                        Some((state, block, _, _)) if block == want => {
                            if block == Block::Transform {
                                (self.state.ctm, self.state.ctm_end, self.state.active) =
                                    (state.ctm, state.ctm_end, state.active);
                            } else {
                                self.state = state;
                            }
                        }
                        Some((_, block, f, l)) => {
                            return Err(err(format!("{name} does not match the {block:?}Begin of {}:{l}", f.display())))
                        }
                        None => return Err(err(format!("unmatched {name} encountered"))),
                    }
                }
                "ObjectBegin" => {
                    let n = args.string()?;
                    if self.object.is_some() {
                        return Err(err("ObjectBegin called inside of instance definition".into()));
                    }
                    if self.objects.contains_key(&n) {
                        return Err(err(format!("{n}: trying to redefine an object instance")));
                    }
                    self.stack.push((self.state.clone(), Block::Object, file.clone(), line));
                    self.object = Some((n, Vec::new()));
                }
                "ObjectEnd" => {
                    let Some((n, shapes)) = self.object.take() else {
                        return Err(err("ObjectEnd called outside of instance definition".into()));
                    };
                    match self.stack.pop() {
                        Some((state, Block::Object, _, _)) => self.state = state,
                        _ => return Err(err("ObjectEnd does not match its ObjectBegin".into())),
                    }
                    self.objects.insert(n, shapes);
                }
                "ObjectInstance" => {
                    let n = args.string()?;
                    self.require_world(&err)?;
                    if self.object.is_some() {
                        return Err(err("ObjectInstance can't be called inside instance definition".into()));
                    }
                    let Some(shapes) = self.objects.get(&n).cloned() else {
                        return Err(err(format!("{n}: named object not defined")));
                    };
                    if self.moving() {
                        return Err(err("an object instance that moves (ActiveTransform) is not modelled by sppm-gpu".into()));
                    }
                    let instance = self.state.ctm;
                    for s in &shapes {
                        let ctm = instance * s.ctm;
                        let state = State {
                            ctm,
                            ctm_end: ctm,
                            active: [true; 2],
                            reverse: s.reverse,
                            material: s.material,
                            area: None,
                            media: s.media.clone(),
                        };
                        self.shape(&s.kind, &s.params, &state)?;
                    }
                }
                "WorldBegin" => {
                    if self.world {
                        return Err(err("WorldBegin given twice".into()));
                    }
                    self.world = true;
                    (self.state.ctm, self.state.ctm_end, self.state.active) = (Mat4::IDENTITY, Mat4::IDENTITY, [true; 2]);
                    self.named_coords.insert("world".into(), [Mat4::IDENTITY; 2]);
                    self.mirror = self.camera_mirror()?;
                }
                "WorldEnd" => self.warnings.push(err("WorldEnd is pbrt-v3's: pbrt-v4 has none (passed over)".into())),
                "Include" | "Import" => {
                    let n = args.string()?;
                    let params = Params::parse(tokens, args.i, file, &self.dir, name.clone(), line)?;
                    params.finish()?;
                    let path = params::resolve(&self.dir, file, &n);
                    self.include(&path, Some((file, line)), depth + 1)?;
                }
                "Camera" | "Film" | "PixelFilter" | "Sampler" | "Integrator" | "Accelerator" | "ColorSpace" => {
                    let kind = args.string()?;
                    let params = Params::parse(tokens, args.i, file, &self.dir, format!("{name} \"{kind}\""), line)?;
                    if self.world {
                        return Err(err(format!("{name} is allowed only before WorldBegin")));
                    }
                    match name.as_str() {
                        "Camera" => {
                            // The camera's transform is the CTM's inverse, and names "camera".
                            if self.moving() {
                                return Err(err("a moving camera (ActiveTransform) is not modelled by sppm-gpu".into()));
                            }
                            let world_from_camera = self.state.ctm.inverse();
                            if !world_from_camera.is_finite() {
                                return Err(err("the camera's transform cannot be inverted".into()));
                            }
                            self.named_coords.insert("camera".into(), [world_from_camera; 2]);
                            let outside = &self.state.media.1;
                            if !outside.is_empty() {
                                self.camera_medium = Some((outside.clone(), err(String::new())));
                            }
                            self.options.camera = Some((kind, params, world_from_camera));
                        }
                        "Film" => self.options.film = Some((kind, params)),
                        "PixelFilter" => self.options.filter = Some((kind, params)),
                        "Sampler" => self.options.sampler = Some((kind, params)),
                        "Integrator" => self.options.integrator = Some((kind, params)),
                        "Accelerator" => params.pass_over(&params.list.iter().map(|p| p.name.as_str()).collect::<Vec<_>>()),
                        _ => {
                            if kind != "srgb" {
                                return Err(err(format!("the color space \"{kind}\" is not modelled by sppm-gpu: srgb")));
                            }
                            params.finish()?;
                        }
                    }
                }
                "Option" => {
                    let params = Params::parse(tokens, args.i, file, &self.dir, name.clone(), line)?;
                    for p in &params.list {
                        self.warnings.push(params.error(&p.name, format!("Option \"{}\" is not applied by sppm-gpu", p.name)));
                    }
                }
                "Material" | "MakeNamedMaterial" | "Texture" | "LightSource" | "AreaLightSource" | "Shape"
                | "MakeNamedMedium" => {
                    let first = args.string()?;
                    let (what, class) = if name == "Texture" {
                        let ty = args.string()?;
                        let class = args.string()?;
                        (format!("Texture \"{first}\" \"{ty}\" \"{class}\""), Some((ty, class)))
                    } else {
                        (format!("{name} \"{first}\""), None)
                    };
                    let params = Params::parse(tokens, args.i, file, &self.dir, what, line)?;
                    if name == "MakeNamedMedium" {
                        // Allowed before WorldBegin too (a camera's medium).
                        self.named_medium(&first, &params)?;
                        continue;
                    }
                    self.require_world(&err)?;
                    match name.as_str() {
                        "Material" => {
                            let index = self.material(&first, &params, None)?;
                            self.state.material = Some(index);
                        }
                        "MakeNamedMaterial" => {
                            let ty = params.string("type")?.map(str::to_owned).ok_or_else(|| {
                                params.error("type", format!("{first}: no \"string type\" parameter for the named material"))
                            })?;
                            if self.named_materials.contains_key(&first) {
                                return Err(err(format!("{first}: named material redefined")));
                            }
                            let index = self.material(&ty, &params, Some(&first))?;
                            self.named_materials.insert(first, index);
                        }
                        "Texture" => {
                            let (ty, class) = class.unwrap();
                            self.texture(&first, &ty, &class, &params)?;
                        }
                        "LightSource" => self.light(&first, &params)?,
                        "AreaLightSource" => self.area_light(&first, &params)?,
                        "Shape" => {
                            let moving = self.moving();
                            if let Some((_, shapes)) = &mut self.object {
                                if self.state.area.is_some() {
                                    return Err(err("area lights not supported with object instancing".into()));
                                }
                                if moving {
                                    return Err(err(
                                        "a shape that moves (ActiveTransform) inside an object is not modelled by sppm-gpu"
                                            .into(),
                                    ));
                                }
                                let s = &self.state;
                                shapes.push(ShapeRecord {
                                    kind: first,
                                    params,
                                    ctm: s.ctm,
                                    reverse: s.reverse,
                                    material: s.material,
                                    media: s.media.clone(),
                                });
                            } else {
                                let state = self.state.clone();
                                self.shape(&first, &params, &state)?;
                            }
                        }
                        _ => unreachable!("MakeNamedMedium is read above"),
                    }
                }
                "NamedMaterial" => {
                    let n = args.string()?;
                    self.require_world(&err)?;
                    let index = *self.named_materials.get(&n).ok_or_else(|| err(format!("{n}: named material not defined")))?;
                    self.state.material = Some(index);
                }
                "MediumInterface" => {
                    let inside = args.string()?;
                    let outside = if matches!(args.tokens.get(*args.i), Some(Token { tok: Tok::Str(_), .. })) {
                        args.string()?
                    } else {
                        inside.clone()
                    };
                    self.state.media = (inside, outside);
                }
                "Attribute" => {
                    return Err(err(
                        "Attribute (default parameters of shapes, lights, materials) is not modelled by sppm-gpu".into()
                    ))
                }
                "ActiveTransform" => {
                    self.state.active = match args.bare_word()?.as_str() {
                        "StartTime" => [true, false],
                        "EndTime" => [false, true],
                        "All" => [true, true],
                        other => return Err(err(format!("unknown argument \"{other}\" to ActiveTransform"))),
                    };
                }
                "TransformTimes" => {
                    let v = args.numbers(2)?;
                    if self.world {
                        return Err(err("TransformTimes is allowed only before WorldBegin".into()));
                    }
                    if !(v[0].is_finite() && v[1].is_finite() && v[1] > v[0]) {
                        return Err(err(format!("the end time {} is not after the start time {}", v[1], v[0])));
                    }
                    self.transform_times = (v[0], v[1]);
                }
                "MakeNamedMaterials" => return Err(err(format!("{name} is not modelled by sppm-gpu"))),
                other => return Err(err(format!("unknown directive \"{other}\""))),
            }
        }
        Ok(())
    }

    /// `ctm = ctm * m`, as pbrt applies a transform directive, to the active CTMs.
    fn concat(&mut self, m: Mat4) {
        let s = &mut self.state;
        if s.active[0] {
            s.ctm *= m;
        }
        if s.active[1] {
            s.ctm_end *= m;
        }
    }

    /// `ctm = m` for the active CTMs.
    fn set_ctm(&mut self, m: Mat4) {
        let s = &mut self.state;
        if s.active[0] {
            s.ctm = m;
        }
        if s.active[1] {
            s.ctm_end = m;
        }
    }

    /// Whether the CTMs at the start and end times differ.
    fn moving(&self) -> bool {
        self.state.ctm != self.state.ctm_end
    }

    /// Refuses a world directive before `WorldBegin`.
    fn require_world(&self, err: &dyn Fn(String) -> SceneError) -> Result<()> {
        if !self.world {
            return Err(err("this directive is allowed only after WorldBegin".into()));
        }
        Ok(())
    }

    /// The mirror of the world that makes our camera show pbrt's image (see the module's notes).
    fn camera_mirror(&self) -> Result<Mat4> {
        let m = self.options.camera.as_ref().map_or(Mat4::IDENTITY, |c| c.2);
        let (pos, right, up, forward) = (
            m.transform_point3(Vec3::ZERO),
            m.transform_vector3(Vec3::X),
            m.transform_vector3(Vec3::Y),
            m.transform_vector3(Vec3::Z),
        );
        if right.dot(forward.cross(up)) > 0.0 {
            return Ok(Mat4::IDENTITY);
        }
        let n = right.normalize_or_zero();
        let linear = glam::Mat3::IDENTITY - 2.0 * glam::Mat3::from_cols(n * n.x, n * n.y, n * n.z);
        Ok(Mat4::from_translation(pos) * Mat4::from_mat3(linear) * Mat4::from_translation(-pos))
    }

    /// Everything read, put together.
    fn finish(&mut self) -> Result<Scene> {
        if let Some((_, block, file, line)) = self.stack.last() {
            return Err(SceneError::new(file, Some(*line), None, format!("{block:?}Begin is not ended")));
        }
        if !self.world {
            return Err(SceneError::new(&self.path, None, Some("WorldBegin"), "the file has no WorldBegin"));
        }
        let (camera, render) = camera::settings(self)?;
        let mut scene = Scene {
            shapes: std::mem::take(&mut self.shapes),
            triangles: std::mem::take(&mut self.triangles),
            spheres: std::mem::take(&mut self.spheres),
            ..Scene::new(
                self.path.clone(),
                render,
                camera,
                std::mem::take(&mut self.materials),
                std::mem::take(&mut self.textures),
                std::mem::take(&mut self.lights),
                std::mem::take(&mut self.media),
            )
        };
        let find = |name: &str, e: &SceneError| {
            let undefined = || SceneError { message: format!("{name}: medium not defined"), ..e.clone() };
            self.named_media.get(name).copied().ok_or_else(undefined)
        };
        for (shape, (inside, outside), e) in &self.shape_media {
            let look = |n: &String| if n.is_empty() { Ok(None) } else { find(n, e).map(Some) };
            let s = &mut scene.shapes[*shape as usize];
            (s.interior, s.exterior) = (look(inside)?, look(outside)?);
        }
        if let Some((name, e)) = &self.camera_medium {
            scene.camera.medium = Some(find(name, e)?);
        }
        // The automatic SPPM radius follows pixel footprints at the look-at point.
        let depth = scene.look_at_scene_depth();
        if scene.camera.aperture_radius == 0.0 {
            scene.camera.focus_distance = depth;
        }
        if !scene.is_lit() {
            return Err(SceneError::new(
                &self.path,
                None,
                Some("LightSource"),
                "the scene has no light: no AreaLightSource on a shape and no LightSource with positive emission",
            ));
        }
        Ok(scene)
    }
}

/// pbrt's `LookAt`: the camera-from-world transform of an eye at `pos` looking at `look`.
fn look_at(pos: Vec3, look: Vec3, up: Vec3) -> std::result::Result<Mat4, String> {
    let dir = (look - pos).normalize_or_zero();
    if dir == Vec3::ZERO {
        return Err("the eye and the point looked at are the same".into());
    }
    let right = up.normalize_or_zero().cross(dir);
    if right.length() < 1e-6 {
        return Err("\"up\" vector and viewing direction passed to LookAt are pointing in the same direction".into());
    }
    let right = right.normalize();
    let new_up = dir.cross(right);
    let world_from_camera = Mat4::from_cols(right.extend(0.0), new_up.extend(0.0), dir.extend(0.0), pos.extend(1.0));
    Ok(world_from_camera.inverse())
}

/// A directive's positional arguments.
struct Args<'t, 'i> {
    tokens: &'t [Token],
    i: &'i mut usize,
    file: &'t Rc<PathBuf>,
    line: usize,
    name: &'t str,
}

impl Args<'_, '_> {
    fn error(&self, m: String) -> SceneError {
        SceneError::new(self.file, Some(self.line), Some(self.name), m)
    }

    /// One quoted string.
    fn string(&mut self) -> Result<String> {
        self.text("a quoted string", |tok| if let Tok::Str(s) = tok { Some(s) } else { None })
    }

    /// One word outside quotes (`ActiveTransform StartTime`).
    fn bare_word(&mut self) -> Result<String> {
        self.text("StartTime, EndTime or All", |tok| if let Tok::Word(w) = tok { Some(w) } else { None })
    }

    /// The next token's text where `pick` takes it, else an error that `expected` it.
    fn text(&mut self, expected: &str, pick: fn(&Tok) -> Option<&String>) -> Result<String> {
        let next = self.tokens.get(*self.i);
        if let Some(text) = next.and_then(|t| pick(&t.tok)) {
            *self.i += 1;
            return Ok(text.clone());
        }
        Err(self.error(format!("expected {expected}, found {}", next.map_or("the end of the file".to_owned(), Token::describe))))
    }

    /// `n` finite numbers, in brackets or not.
    fn numbers(&mut self, n: usize) -> Result<Vec<f32>> {
        let bracket = matches!(self.tokens.get(*self.i), Some(Token { tok: Tok::Open, .. }));
        if bracket {
            *self.i += 1;
        }
        let mut v = Vec::with_capacity(n);
        for _ in 0..n {
            match self.tokens.get(*self.i) {
                Some(Token { tok: Tok::Word(w), .. }) => {
                    let x: f32 = w.parse().map_err(|_| self.error(format!("`{w}` is not a number")))?;
                    if !x.is_finite() {
                        return Err(self.error(format!("`{w}` is not a finite number")));
                    }
                    v.push(x);
                    *self.i += 1;
                }
                other => {
                    return Err(self.error(format!(
                        "expects {n} numbers, found {} after {}",
                        other.map_or("the end of the file".to_owned(), Token::describe),
                        v.len()
                    )))
                }
            }
        }
        if bracket {
            match self.tokens.get(*self.i) {
                Some(Token { tok: Tok::Close, .. }) => *self.i += 1,
                _ => return Err(self.error(format!("expects {n} numbers and `]`"))),
            }
        }
        Ok(v)
    }

    /// A 4x4 matrix's 16 numbers.
    fn matrix(&mut self) -> Result<[f32; 16]> {
        let v = self.numbers(16)?;
        Ok(std::array::from_fn(|k| v[k]))
    }
}
