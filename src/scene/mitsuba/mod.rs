//! Mitsuba's scene XML (versions 0.5/0.6 and 2/3), read into the same [`Scene`] as our TOML,
//! rendered as Mitsuba 3 renders it. Every element is either modelled exactly, or refused
//! with an error naming the file, line and element; only what cannot change the image (a
//! film's file format, tone mapping of an LDR film, a sampler's kind, how many photons an
//! integrator of Mitsuba 0.6 schedules at once) is passed over, with a warning naming file,
//! line and parameter where it has no counterpart here. A file is read as its own version
//! reads it: in a 0.x scene a parameter that the plugin does not query is a warning, as in
//! Mitsuba 0.5/0.6, and in a 2.x/3.x scene an error, as in Mitsuba 3 (props.rs). Mitsuba
//! 3's parameters are read as Mitsuba 3 reads them in files of every version; those only
//! Mitsuba 0.5/0.6 have are mapped where we have their counterpart, warned where they change
//! only the noise, the speed or the scheduling, and refused where ignoring them would change
//! the image (each plugin's module lists them).
//!
//! - `xml.rs`: files, `<include>`, `<default>`, `$name` and `-D`, camelCase names of 0.x files.
//! - `props.rs`: a plugin's typed parameters, each of which must be read.
//! - `bsdf.rs`: `diffuse`, `twosided`, `dielectric`, `roughdielectric`, `conductor`,
//!   `roughconductor`, `plastic`, `roughplastic`, `thindielectric`, `null` (the list of
//!   those refused by name is there), into [`crate::scene::material`]'s families.
//! - `shape.rs`: `obj`, `ply`, `serialized`, `rectangle`, `cube`, `disk`, `sphere`,
//!   `shapegroup` / `instance`, area emitters.
//! - `texture.rs`: `bitmap` and `checkerboard`, on a diffuse `reflectance`, a conductor's
//!   `specular_reflectance` or a plastic's `diffuse_reflectance`.
//! - `sensor.rs`: `perspective`, `thinlens`, the film, its pixel filter and the sampler.
//! - `emitter.rs`: `point`, `directional`, `spot`, `constant` and `envmap` emitters (and the
//!   `area` emitters of shape.rs), into [`crate::scene::emitter`]'s kinds.
//! - `integrator.rs`: the integrator, as our method and render settings.
//!
//! Conventions taken from Mitsuba 3 (and checked against its renders, tests/suite/mitsuba_xml.rs):
//! BSDFs are one-sided unless wrapped in `twosided`; a shape without a BSDF is a one-sided
//! `diffuse` of reflectance 0.5, or 0 when it emits; meshes without `face_normals` are smooth, with the file's
//! normals or else angle-weighted vertex normals; the default pixel filter is `gaussian`.

mod bsdf;
mod emitter;
mod integrator;
mod medium;
mod props;
mod sensor;
mod shape;
pub(crate) mod spectra;
mod texture;
mod xml;

use super::mesh::PrimitiveBudget;
use super::{Light, Material, Medium, Scene, SceneError, Shape, Sphere, Texture, Triangle};
use std::collections::HashMap;
use std::path::Path;
use xml::Node;

pub use xml::snake_case;

pub(crate) use bsdf::NAMED_CONDUCTORS;

type Result<T> = std::result::Result<T, SceneError>;

/// Reads Mitsuba scene XML `path`; `defines` are the command line's `-D name=value`. Its
/// warnings are printed (to stderr), whether or not it loads.
pub fn load(path: &Path, defines: &[(String, String)]) -> Result<Scene> {
    let (scene, warnings) = load_with_warnings(path, defines);
    for warning in &warnings {
        eprintln!("warning: {warning}");
    }
    scene
}

/// Reads Mitsuba scene XML `path` as [`load`] does, giving back its warnings, each with the
/// file, line and parameter it is about, in the order met, rather than printing them.
pub fn load_with_warnings(path: &Path, defines: &[(String, String)]) -> (Result<Scene>, Vec<SceneError>) {
    let (root, dirs) = match xml::read_scene(path, defines) {
        Ok(read) => read,
        Err(e) => return (Err(e), Vec::new()),
    };
    let scene = SceneReader::new(&root, dirs).and_then(|mut reader| {
        reader.read(&root)?;
        reader.finish(path)
    });
    (scene, root.reading.take_warnings())
}

/// The scene as it is being read.
struct SceneReader<'a> {
    /// Elements with an `id`, for `<ref>`.
    ids: HashMap<&'a str, &'a Node>,
    /// How many instances refer to each shapegroup (by address).
    instances: HashMap<*const Node, u64>,
    /// The primitives one copy of a shapegroup adds, once its first instance is read.
    copy_size: HashMap<*const Node, u64>,
    /// Primitives that instances not yet read will add, counted when their group's first
    /// instance was: the budget is checked on them before any is copied.
    reserved: u64,
    /// How many primitives the scene may have on this machine.
    budget: PrimitiveBudget,
    /// The instance being read and its group, for messages.
    instance: Option<(&'a Node, &'a Node)>,
    /// Materials so far, and the material of each BSDF element read (by address), so that a
    /// BSDF shared by reference is one material.
    materials: Vec<Material>,
    material_of: HashMap<*const Node, u32>,
    /// Textures so far, and the texture of each texture element read (by address).
    textures: Vec<Texture>,
    texture_of: HashMap<*const Node, u32>,
    shapes: Vec<Shape>,
    triangles: Vec<Triangle>,
    spheres: Vec<Sphere>,
    lights: Vec<Light>,
    /// Media so far, and the medium of each medium element read (by address), so that a
    /// medium shared by reference is one.
    media: Vec<Medium>,
    medium_of: HashMap<*const Node, u32>,
    sensor: Option<sensor::SensorSettings>,
    integrator: Option<&'a Node>,
    /// The directories `<path>` added and the scene file's, where files named in included
    /// fragments are also looked for ([`xml::resolve`]).
    root: Vec<std::path::PathBuf>,
}

impl<'a> SceneReader<'a> {
    /// Collects the ids of every element under `root`.
    fn new(root: &'a Node, dirs: Vec<std::path::PathBuf>) -> Result<Self> {
        let mut ids = HashMap::new();
        fn walk<'a>(node: &'a Node, ids: &mut HashMap<&'a str, &'a Node>) -> Result<()> {
            // A <ref>'s id names another element.
            if let Some(id) = node.attr("id").filter(|_| node.tag != "ref") {
                if let Some(previous) = ids.insert(id, node) {
                    return Err(node.error(
                        Some("id"),
                        format!("id \"{id}\" is already taken by {} on line {}", previous.describe(), previous.line),
                    ));
                }
            }
            node.children.iter().try_for_each(|c| walk(c, ids))
        }
        walk(root, &mut ids)?;
        let mut check = References { ids: &ids, state: HashMap::new(), instances: HashMap::new() };
        check.visit(root, 1)?;
        let instances = check.instances;
        Ok(SceneReader {
            ids,
            instances,
            copy_size: HashMap::new(),
            reserved: 0,
            budget: PrimitiveBudget::new(),
            instance: None,
            materials: Vec::new(),
            material_of: HashMap::new(),
            textures: Vec::new(),
            texture_of: HashMap::new(),
            shapes: Vec::new(),
            triangles: Vec::new(),
            spheres: Vec::new(),
            lights: Vec::new(),
            media: Vec::new(),
            medium_of: HashMap::new(),
            sensor: None,
            integrator: None,
            root: dirs,
        })
    }

    /// The triangles and spheres so far, and those promised to instances not yet read.
    fn primitives(&self) -> u64 {
        (self.triangles.len() + self.spheres.len()) as u64 + self.reserved
    }

    /// Refuses adding `count` primitives where the scene would outgrow the machine's memory
    /// ([`PrimitiveBudget`]), with the error at `node` about `key`.
    fn reserve(&self, count: usize, node: &Node, key: Option<&str>) -> Result<()> {
        let within = match self.instance {
            Some((instance, group)) => format!(
                " (within the instance of shapegroup \"{}\" on line {})",
                group.attr("id").unwrap_or_default(),
                instance.line
            ),
            None => String::new(),
        };
        self.budget.check(self.primitives(), count as u64, &within).map_err(|e| node.error(key, e))
    }

    /// The element a `<ref id=".."/>` names, which must have tag `tag` (or any object tag
    /// when `tag` is empty).
    fn deref(&self, node: &'a Node, tag: &str) -> Result<&'a Node> {
        if node.tag != "ref" {
            return Ok(node);
        }
        node.allow_attrs(&["id", "name"])?;
        let id = node.req_attr("id")?;
        let target = self.ids.get(id).ok_or_else(|| node.error(Some("id"), format!("no element has id \"{id}\"")))?;
        if !tag.is_empty() && target.tag != tag {
            return Err(
                node.error(Some("id"), format!("\"{id}\" is {} (line {}), not a <{tag}>", target.describe(), target.line))
            );
        }
        Ok(target)
    }

    /// The children of `<scene>`.
    fn read(&mut self, root: &'a Node) -> Result<()> {
        root.allow_attrs(&["version"])?;
        for node in &root.children {
            match node.tag.as_str() {
                "shape" => self.shape(node, glam::Mat4::IDENTITY)?,
                // An area emitter declared apart, for the shapes that refer to it.
                "emitter" if node.attr("type") == Some("area") && node.attr("id").is_some() => {}
                "emitter" => emitter::light(node, &mut self.lights, &self.root)?,
                "sensor" => {
                    if self.sensor.is_some() {
                        return Err(node.error(None, "a second <sensor>: sppm-gpu renders one camera"));
                    }
                    let settings = sensor::sensor(node, &mut |m| self.medium(m))?;
                    self.sensor = Some(settings);
                }
                "integrator" => {
                    if self.integrator.is_some() {
                        return Err(node.error(None, "a second <integrator>"));
                    }
                    self.integrator = Some(node);
                }
                // Declared for reference: read when a shape or BSDF refers to them. One without
                // an id cannot be referred to: Mitsuba names it for itself and never uses it
                // (Bitterli's staircase wraps a named BSDF in an unnamed bump map), so it is
                // passed over with a warning; a named BSDF nested in it is still found by its id.
                "bsdf" | "texture" => {
                    if node.attr("id").is_none() {
                        node.warn(None, format!("{} has no id: no shape can refer to it, so it is not used", node.describe()));
                    }
                }
                // Declared for reference, and checked as Mitsuba instantiates them: in the scene's
                // media once the sensor or a shape refers to them.
                "medium" => {
                    node.req_attr("id")?;
                    self.read_medium(node)?;
                }
                "phase" => {
                    node.req_attr("id")?;
                    medium::check_phase(node)?;
                }
                "volume" => {
                    return Err(node.error(
                        None,
                        format!(
                            "{}: volume grids make heterogeneous media, which sppm-gpu does not render (only homogeneous \
                             participating media)",
                            node.describe()
                        ),
                    ))
                }
                "path" => {
                    return Err(node.error(None, "<path> (a search path) is not read: give file names relative to the scene"))
                }
                // Mitsuba 0.6's scene takes the settings of its kd-tree's build (`kdStopPrims`,
                // `kdIntersectionCost`, ...): its speed, not the image.
                tag if node.legacy() && props::PROPERTY_TAGS.contains(&tag) => {
                    let name = node.req_attr("name")?;
                    let why = if name.starts_with("kd_") {
                        "it sets how Mitsuba 0.6 builds its kd-tree, which changes the speed, not the image"
                    } else {
                        "Mitsuba 0.5/0.6's scene does not query it either (and warns)"
                    };
                    node.warn(Some(name), format!("the scene's {name} is not applied: {why}"));
                }
                other => return Err(node.error(None, format!("<{other}> is not an element of a Mitsuba <scene>"))),
            }
        }
        Ok(())
    }

    /// Everything read, put together.
    fn finish(self, path: &Path) -> Result<Scene> {
        let Some(sensor) = self.sensor else {
            return Err(SceneError::new(path, None, Some("sensor"), "the scene has no <sensor>: sppm-gpu needs a camera"));
        };
        let shading_normals = self.triangles.iter().any(|t| t.n.is_some());
        let render = integrator::render_settings(&sensor, self.integrator, shading_normals)?;
        let mut scene = Scene {
            shapes: self.shapes,
            triangles: self.triangles,
            spheres: self.spheres,
            ..Scene::new(path.to_path_buf(), render, sensor.camera, self.materials, self.textures, self.lights, self.media)
        };
        // Our camera's look-at point sets the automatic SPPM radius (pixel footprints at its
        // distance); Mitsuba's `lookat` target is often one unit ahead.
        scene.look_at_scene_depth();
        if !scene.is_lit() {
            return Err(SceneError::new(
                path,
                None,
                Some("emitter"),
                "the scene has no light: no area emitter with positive radiance, no point, directional, spot or constant emitter",
            ));
        }
        Ok(scene)
    }
}

/// The reference graph, checked before anything is read: the readers follow each `<ref>`
/// into the element it names, so a cycle would recurse without end and a long chain
/// overflow the stack. Refuses a `<ref>` to an element around it (a cycle), nesting deeper
/// than [`xml::MAX_DEPTH`] counting the elements references bring in, and what Mitsuba's
/// shapegroup refuses (`shapegroup.cpp` of Mitsuba 0.6 and 3 alike): an instance or a
/// shapegroup inside one ("Nested instancing is not permitted") and a shape that emits
/// ("Instancing of emitters is not supported"). Counts the instances of each group. Each
/// element with an id is walked once (its height kept), so the walk is linear.
struct References<'a, 'm> {
    ids: &'m HashMap<&'a str, &'a Node>,
    /// Elements with an id: `None` while being walked, then the height of their subtree.
    state: HashMap<*const Node, Option<usize>>,
    instances: HashMap<*const Node, u64>,
}

impl<'a> References<'a, '_> {
    /// Walks `node`, at `depth`, and gives the height of its subtree with references
    /// followed (1 for an element without children).
    fn visit(&mut self, node: &'a Node, depth: usize) -> Result<usize> {
        let too_deep = |at: &Node| {
            at.error(
                None,
                format!(
                    "{} nests more than {} elements deep, counting the elements <ref>s bring in: a Mitsuba scene nests \
                     about 10 deep",
                    at.describe(),
                    xml::MAX_DEPTH
                ),
            )
        };
        if depth > xml::MAX_DEPTH {
            return Err(too_deep(node));
        }
        let key = node as *const Node;
        let has_id = node.tag != "ref" && node.attr("id").is_some();
        if has_id {
            // Open elements are caught at the <ref> that names them.
            if let Some(&Some(height)) = self.state.get(&key) {
                return if depth + height - 1 > xml::MAX_DEPTH { Err(too_deep(node)) } else { Ok(height) };
            }
            self.state.insert(key, None);
        }
        if node.tag == "shape" && node.attr("type") == Some("shapegroup") {
            self.check_group(node)?;
        }
        let instance = node.tag == "shape" && node.attr("type") == Some("instance");
        let mut height = 1;
        for child in &node.children {
            let below = if child.tag == "ref" {
                let Some(target) = child.attr("id").and_then(|id| self.ids.get(id).copied()) else {
                    continue; // named nowhere: SceneReader::deref says so where it is read
                };
                if instance {
                    *self.instances.entry(target as *const Node).or_default() += 1;
                }
                match self.state.get(&(target as *const Node)) {
                    Some(None) => {
                        return Err(child.error(
                            Some("id"),
                            format!(
                                "<ref id=\"{}\"> refers to {} on line {}, which contains it: a reference cycle",
                                child.attr("id").unwrap_or_default(),
                                target.describe(),
                                target.line
                            ),
                        ))
                    }
                    // The element named is read in the <ref>'s place.
                    _ => self.visit(target, depth + 1)?,
                }
            } else {
                if instance && child.tag == "shape" && child.attr("type") == Some("shapegroup") {
                    *self.instances.entry(child as *const Node).or_default() += 1;
                }
                self.visit(child, depth + 1)?
            };
            height = height.max(below + 1);
        }
        if has_id {
            self.state.insert(key, Some(height));
        }
        Ok(height)
    }

    /// Mitsuba's rules for what a shapegroup holds.
    fn check_group(&self, group: &Node) -> Result<()> {
        let id = group.attr("id").unwrap_or_default();
        for child in group.children.iter().filter(|c| c.tag == "shape") {
            if let Some(kind @ ("instance" | "shapegroup")) = child.attr("type") {
                return Err(child.error(
                    Some("type"),
                    format!(
                        "a{} {kind} inside shapegroup \"{id}\" (line {}): nested instancing is not permitted, as \
                         Mitsuba refuses it",
                        if kind == "instance" { "n" } else { "" },
                        group.line
                    ),
                ));
            }
            for object in &child.children {
                let target = match object.tag.as_str() {
                    "ref" => object.attr("id").and_then(|id| self.ids.get(id).copied()),
                    _ => Some(object),
                };
                if target.is_some_and(|t| t.tag == "emitter") {
                    return Err(object.error(
                        None,
                        format!(
                            "an emitter on a shape inside shapegroup \"{id}\" (line {}): instancing of emitters is \
                             not supported, as Mitsuba refuses it",
                            group.line
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}
