//! The XML layer of Mitsuba's scene format: files read into one tree of [`Node`]s, each
//! knowing its file and line, with the format's own structure resolved as Mitsuba 3 resolves
//! it (`src/core/xml.cpp` there):
//! - `<default name="n" value="v"/>` sets parameter `n` unless the command line's `-D n=v`
//!   (or an earlier default) did; `$n` in any later attribute is replaced by its value.
//! - `<include filename="f"/>` splices in the children of `f`'s `<scene>` (relative to the
//!   including file), refusing a file that includes itself, directly or not.
//! - `<path value="d"/>` puts directory `d` (relative to the file that names it, else found
//!   as files are) first among the places files are looked for, as Mitsuba's file resolver
//!   does ([`resolve`]).
//! - Version 0.x files name their parameters in camelCase (`toWorld`, `intIOR`); Mitsuba 3
//!   reads them as snake_case (`to_world`, `int_ior`), and so do we. The names of `<default>`s
//!   stay as written, as the `$name`s that use them.
//! - The outermost file's version says which Mitsuba the scene is read as ([`Node::legacy`]):
//!   a parameter that no plugin reads is a warning in a 0.x scene, as Mitsuba 0.5/0.6 warn and
//!   render, and an error in a 2.x/3.x scene, as Mitsuba 3 refuses it (props.rs).
//!
//! A hostile file must not take the process down, so reading has limits, each an error at the
//! element that passes it: elements nest at most [`MAX_DEPTH`] deep (through includes too;
//! roxmltree parses without recursing, but this reader and those after it recurse once a
//! level), a scene has at most [`MAX_ELEMENTS`] elements and reads at most [`MAX_INCLUDES`]
//! includes (an included file counted each time, so that files including the next twice
//! cannot multiply without end), and the XML read plus what `$name`s expand to is at most
//! [`files::max_bytes`](crate::scene::files::max_bytes).

use super::super::SceneError;
use std::cell::{Cell, RefCell};
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::rc::Rc;

type Result<T> = std::result::Result<T, SceneError>;

/// How deep elements may nest, `<scene>` at depth 1, an included file's elements at the
/// depth of the `<include>` they replace. A real scene nests about 10 deep (scene, shape,
/// BSDF, texture, transform, operation); the readers recurse once a level.
pub const MAX_DEPTH: usize = 256;

/// The elements a scene may have, an included file's counted each time it is included:
/// about 300 bytes each once read, so at most some 1.2 GiB.
pub const MAX_ELEMENTS: usize = 1 << 22;

/// The `<include>`s a scene may read, a file counted each time it is included: plenty for a
/// scene assembled from fragments, while a chain of files each including the next twice
/// would read 2^depth.
pub const MAX_INCLUDES: usize = 1 << 14;

/// An XML element after includes, defaults and substitution.
#[derive(Clone, Debug)]
pub struct Node {
    /// The element's tag (`shape`, `float`, `rgb`, ...).
    pub tag: String,
    /// Attributes in file order, `$name` substituted.
    pub attrs: Vec<(String, String)>,
    /// Child elements (comments and text dropped).
    pub children: Vec<Node>,
    /// The file the element is in.
    pub file: Rc<PathBuf>,
    /// Its 1-based line.
    pub line: usize,
    /// What the scene's elements share: its version, its warnings.
    pub reading: Rc<Reading>,
}

/// What every element of one scene shares.
#[derive(Debug)]
pub struct Reading {
    /// Major version of the outermost file, which says whose Mitsuba reads the scene: 0 for
    /// Mitsuba 0.5/0.6, whose plugins warn about a parameter they do not query and render, 2
    /// or 3 for Mitsuba 3 (and 2), which refuses it.
    version: Cell<u32>,
    /// Warnings so far, in the order met.
    warnings: RefCell<Vec<SceneError>>,
}

impl Reading {
    /// The warnings so far, taken.
    pub fn take_warnings(&self) -> Vec<SceneError> {
        self.warnings.take()
    }
}

impl Node {
    /// Attribute `name`, when present.
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs.iter().find(|(k, _)| k == name).map(|(_, v)| v.as_str())
    }

    /// An error at this element; `key` names what in it is wrong.
    pub fn error(&self, key: Option<&str>, message: impl Into<String>) -> SceneError {
        SceneError::new(&self.file, Some(self.line), key, message)
    }

    /// Attribute `name`, or an error naming it.
    pub fn req_attr(&self, name: &str) -> Result<&str> {
        self.attr(name).ok_or_else(|| self.error(Some(name), format!("<{}> needs a `{name}` attribute", self.tag)))
    }

    /// Refuses attributes other than `allowed`.
    pub fn allow_attrs(&self, allowed: &[&str]) -> Result<()> {
        match self.attrs.iter().find(|(k, _)| !allowed.contains(&k.as_str())) {
            Some((k, _)) => Err(self.error(Some(k), format!("<{}> takes no attribute `{k}`", self.tag))),
            None => Ok(()),
        }
    }

    /// Whether the scene is read as Mitsuba 0.5/0.6 read it (its outermost file is 0.x).
    pub fn legacy(&self) -> bool {
        self.reading.version.get() == 0
    }

    /// A warning at this element, about `key` when it names one.
    /// The same warning twice (a parameter read twice, as a diffuse reflectance is: once to
    /// see whether it is a texture) is given once.
    pub fn warn(&self, key: Option<&str>, message: impl Into<String>) {
        let warning = self.error(key, message);
        let mut warnings = self.reading.warnings.borrow_mut();
        if !warnings.contains(&warning) {
            warnings.push(warning);
        }
    }

    /// `<tag type="...">` or `<tag>` with its name, for messages.
    pub fn describe(&self) -> String {
        match (self.attr("type"), self.attr("name")) {
            (Some(t), _) => format!("<{} type=\"{t}\">", self.tag),
            (None, Some(n)) => format!("<{} name=\"{n}\">", self.tag),
            _ => format!("<{}>", self.tag),
        }
    }
}

/// The root `<scene>` of `path` with includes spliced in (its [`Node::reading`] has the
/// outermost file's version), and the directories files are looked for in ([`resolve`]).
pub fn read_scene(path: &Path, defines: &[(String, String)]) -> Result<(Node, Vec<PathBuf>)> {
    let root = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let reading = Rc::new(Reading { version: Cell::new(3), warnings: RefCell::new(Vec::new()) });
    let mut reader = Reader {
        params: HashMap::new(),
        used: HashSet::new(),
        stack: Vec::new(),
        reading,
        dirs: vec![root],
        elements: 0,
        includes: 0,
        bytes: 0,
        max_bytes: crate::scene::files::max_bytes(),
    };
    for (name, value) in defines {
        if !is_param_name(name) {
            return Err(SceneError::new(path, None, Some(name), format!("-D {name}={value}: not a parameter name")));
        }
        reader.params.insert(name.clone(), value.clone());
    }
    let root = reader.file(path, None, 1)?;
    // A -D the scene never reads is most likely misspelt.
    let mut warned = HashSet::new();
    for (name, _) in defines {
        if !reader.used.contains(name) && warned.insert(name) {
            let value = &reader.params[name];
            let message = format!("-D {name}={value}: the scene has no ${name} and no <default name=\"{name}\">");
            reader.reading.warnings.borrow_mut().push(SceneError::new(path, None, None, message));
        }
    }
    Ok((root, reader.dirs))
}

/// What reading the files keeps: parameters, the chain of includes, what the elements share.
struct Reader {
    params: HashMap<String, String>,
    /// Parameters a `$name` or a `<default>` named.
    used: HashSet<String>,
    /// The files being read, outermost first, canonicalized: an include cycle repeats one.
    stack: Vec<PathBuf>,
    /// The version of the outermost file (set as it is read, before any element) and the
    /// warnings.
    reading: Rc<Reading>,
    /// The directories `<path>` added, newest first, then the outermost file's.
    dirs: Vec<PathBuf>,
    /// Elements and includes read so far (each inclusion counted).
    elements: usize,
    includes: usize,
    /// Bytes of XML read (each inclusion counted) and added by `$name` expansion, and their
    /// cap.
    bytes: u64,
    max_bytes: u64,
}

/// Where each line of a file starts, for the line of an element in O(log n) (roxmltree's
/// `text_pos_at` scans from the start each time: quadratic over a large file).
struct Lines(Vec<usize>);

impl Lines {
    fn new(text: &str) -> Self {
        Lines(text.bytes().enumerate().filter(|&(_, b)| b == b'\n').map(|(i, _)| i).collect())
    }

    /// The 1-based line of byte `pos`.
    fn at(&self, pos: usize) -> usize {
        self.0.partition_point(|&newline| newline < pos) + 1
    }
}

/// A file named in `file`: relative to `file`'s directory where it is there, else to the
/// first of `dirs` (those `<path>` added, newest first, then the scene's directory) that has
/// it, as Mitsuba's file resolver, which holds the scene's directory and the `<path>`s, finds
/// files named in included fragments. Where none has it, the name relative to `file`, for
/// the error.
pub fn resolve(name: &str, file: &Path, dirs: &[PathBuf]) -> PathBuf {
    let local = file.parent().unwrap_or(Path::new("")).join(name);
    if local.exists() {
        return local;
    }
    dirs.iter().map(|d| d.join(name)).find(|p| p.exists()).unwrap_or(local)
}

impl Reader {
    /// Reads `path`'s `<scene>` element, at `depth` ([`MAX_DEPTH`]). `from` is the
    /// `<include>` that names it.
    fn file(&mut self, path: &Path, from: Option<&Node>, depth: usize) -> Result<Node> {
        let at = |message: String| match from {
            Some(node) => node.error(Some("filename"), message),
            None => SceneError::new(path, None, None, message),
        };
        let bytes = crate::scene::files::read(path).map_err(|e| at(format!("cannot read {}: {e}", path.display())))?;
        self.bytes += bytes.len() as u64;
        if self.bytes > self.max_bytes {
            return Err(at(format!(
                "the scene's XML comes to more than {} bytes here (an included file counted each time it is included)",
                self.max_bytes
            )));
        }
        let text = String::from_utf8(bytes).map_err(|e| {
            let line = e.as_bytes()[..e.utf8_error().valid_up_to()].iter().filter(|&&b| b == b'\n').count() + 1;
            SceneError::new(path, Some(line), None, "the file is not UTF-8 text")
        })?;
        let canonical = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
        if self.stack.contains(&canonical) {
            return Err(at(format!("{} includes itself (through {} files)", path.display(), self.stack.len())));
        }
        if self.stack.len() >= 64 {
            return Err(at("includes nest more than 64 files deep".into()));
        }
        let options = roxmltree::ParsingOptions { allow_dtd: false, ..Default::default() };
        let document = roxmltree::Document::parse_with_options(&text, options).map_err(|e| {
            let pos = e.pos();
            SceneError::new(path, Some(pos.row as usize), None, format!("malformed XML: {e}"))
        })?;
        let file = Rc::new(path.to_path_buf());
        let root = document.root_element();
        let lines = Lines::new(&text);
        let line = |n: roxmltree::Node| lines.at(n.range().start);
        if root.tag_name().name() != "scene" {
            return Err(SceneError::new(path, Some(line(root)), None, "the root element is not <scene>"));
        }
        let version = root.attribute("version").unwrap_or("3.0.0");
        let major = version.split('.').next().and_then(|m| m.trim().parse::<u32>().ok()).ok_or_else(|| {
            SceneError::new(path, Some(line(root)), Some("version"), format!("version \"{version}\" is not a version number"))
        })?;
        if !matches!(major, 0 | 2 | 3) {
            return Err(SceneError::new(
                path,
                Some(line(root)),
                Some("version"),
                format!("version {version}: Mitsuba scene files are 0.x, 2.x or 3.x"),
            ));
        }
        if self.stack.is_empty() {
            self.reading.version.set(major);
        }
        self.stack.push(canonical);
        let result = self.element(root, &lines, &file, major, depth);
        self.stack.pop();
        result
    }

    /// Converts `element`, at `depth`, and its subtree, resolving defaults, substitution and
    /// includes.
    fn element(&mut self, element: roxmltree::Node, lines: &Lines, file: &Rc<PathBuf>, major: u32, depth: usize) -> Result<Node> {
        let line = lines.at(element.range().start);
        let mut node = Node {
            tag: element.tag_name().name().to_owned(),
            attrs: Vec::new(),
            children: Vec::new(),
            file: file.clone(),
            line,
            reading: self.reading.clone(),
        };
        self.elements += 1;
        if self.elements > MAX_ELEMENTS {
            return Err(node.error(
                None,
                format!(
                    "the scene has more than {MAX_ELEMENTS} elements (an included file's counted each time it is \
                     included): more than sppm-gpu reads"
                ),
            ));
        }
        if element.tag_name().namespace().is_some() {
            return Err(node.error(None, "XML namespaces are not part of Mitsuba's format"));
        }
        for a in element.attributes() {
            let value = self.substitute(a.value(), &node, a.name())?;
            // What `$name`s added counts with the XML read: defaults that repeat one another
            // would otherwise grow without end.
            self.bytes += value.len().saturating_sub(a.value().len()) as u64;
            // Mitsuba 3 upgrades 0.x files' parameter names from camelCase to snake_case.
            let upgrade = major == 0 && a.name() == "name" && node.tag != "default";
            let value = if upgrade { snake_case(&value) } else { value };
            node.attrs.push((a.name().to_owned(), value));
        }
        for child in element.children() {
            if child.is_text() && !child.text().unwrap_or("").trim().is_empty() {
                let line = lines.at(child.range().start);
                return Err(SceneError::new(
                    file,
                    Some(line),
                    None,
                    format!("text inside <{}>: Mitsuba's format has none", node.tag),
                ));
            }
            if !child.is_element() {
                continue;
            }
            // Checked before recursing: the stack holds a frame a level.
            if depth >= MAX_DEPTH {
                return Err(SceneError::new(
                    file,
                    Some(lines.at(child.range().start)),
                    None,
                    format!(
                        "<{}> nests more than {MAX_DEPTH} elements deep (counting through includes): a Mitsuba scene \
                         nests about 10 deep",
                        child.tag_name().name()
                    ),
                ));
            }
            let child = self.element(child, lines, file, major, depth + 1)?;
            match child.tag.as_str() {
                "default" => {
                    child.allow_attrs(&["name", "value"])?;
                    let name = child.req_attr("name")?;
                    if !is_param_name(name) {
                        return Err(child.error(Some("name"), format!("\"{name}\" is not a parameter name")));
                    }
                    let value = child.req_attr("value")?.to_owned();
                    self.used.insert(name.to_owned());
                    self.params.entry(name.to_owned()).or_insert(value);
                }
                "include" => {
                    child.allow_attrs(&["filename"])?;
                    let name = child.req_attr("filename")?;
                    self.includes += 1;
                    if self.includes > MAX_INCLUDES {
                        return Err(child.error(
                            Some("filename"),
                            format!(
                                "the scene reads more than {MAX_INCLUDES} includes (a file counted each time it is \
                                 included): includes that multiply are refused"
                            ),
                        ));
                    }
                    // The included `<scene>` stands at this element's depth: its children
                    // take the `<include>`'s place.
                    let included = self.file(&resolve(name, file, &self.dirs), Some(&child), depth)?;
                    node.children.extend(included.children);
                }
                "path" => {
                    child.allow_attrs(&["value"])?;
                    if node.tag != "scene" {
                        return Err(child.error(None, "<path> belongs directly in <scene>"));
                    }
                    let value = child.req_attr("value")?;
                    let dir = resolve(value, file, &self.dirs);
                    if !dir.is_dir() {
                        return Err(child.error(Some("value"), format!("{} is not a directory", dir.display())));
                    }
                    // Ahead of every directory so far, as Mitsuba's FileResolver::prepend.
                    self.dirs.insert(0, dir);
                }
                _ => node.children.push(child),
            }
        }
        Ok(node)
    }

    /// `text` with each `$name` replaced by its parameter's value.
    fn substitute(&mut self, text: &str, node: &Node, attr: &str) -> Result<String> {
        let mut out = String::with_capacity(text.len());
        let mut rest = text;
        while let Some(at) = rest.find('$') {
            out.push_str(&rest[..at]);
            let after = &rest[at + 1..];
            let len = after.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(after.len());
            let name = &after[..len];
            if name.is_empty() {
                return Err(node.error(Some(attr), format!("a `$` not followed by a parameter name in \"{text}\"")));
            }
            match self.params.get(name) {
                // Bounded as it grows: the budget of `bytes` is checked before the value is kept.
                Some(value)
                    if (out.len() + value.len()) as u64 > text.len() as u64 + self.max_bytes.saturating_sub(self.bytes) =>
                {
                    return Err(node.error(
                        Some(attr),
                        format!(
                            "${name} expands the scene's XML to more than {} bytes (defaults that repeat one another)",
                            self.max_bytes
                        ),
                    ))
                }
                Some(value) => {
                    out.push_str(value);
                    self.used.insert(name.to_owned());
                }
                None => {
                    return Err(node.error(
                        Some(attr),
                        format!("${name} is not defined: give it a <default name=\"{name}\" value=\"...\"/> or -D {name}=..."),
                    ))
                }
            }
            rest = &after[len..];
        }
        out.push_str(rest);
        Ok(out)
    }
}

/// Whether `name` can be a `$parameter`: letters, digits and underscores.
fn is_param_name(name: &str) -> bool {
    !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// `toWorld` -> `to_world`, `intIOR` -> `int_ior`: an underscore between a lower-case letter
/// or digit and the capital after it, then everything lower case (Mitsuba 3's upgrade of 0.x
/// files).
pub fn snake_case(name: &str) -> String {
    let mut out = String::with_capacity(name.len() + 4);
    let mut prev: Option<char> = None;
    for c in name.chars() {
        if c.is_ascii_uppercase() && prev.is_some_and(|p| p.is_ascii_lowercase() || p.is_ascii_digit()) {
            out.push('_');
        }
        out.push(c.to_ascii_lowercase());
        prev = Some(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{snake_case, Lines};

    #[test]
    fn lines_are_found_by_byte() {
        let lines = Lines::new("a\nbc\n\nd");
        let found: Vec<usize> = (0..8).map(|pos| lines.at(pos)).collect();
        // Each newline belongs to the line it ends.
        assert_eq!(found, [1, 1, 2, 2, 2, 3, 4, 4]);
    }

    #[test]
    fn camel_case_names_become_snake_case() {
        for (camel, snake) in [
            ("toWorld", "to_world"),
            ("intIOR", "int_ior"),
            ("extIOR", "ext_ior"),
            ("sampleCount", "sample_count"),
            ("maxDepth", "max_depth"),
            ("fovAxis", "fov_axis"),
            ("specularReflectance", "specular_reflectance"),
            ("shapeIndex", "shape_index"),
            ("cropOffsetX", "crop_offset_x"),
            ("radiance", "radiance"),
            ("max_depth", "max_depth"),
        ] {
            assert_eq!(snake_case(camel), snake, "{camel}");
        }
    }
}
