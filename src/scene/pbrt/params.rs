//! A directive's parameter list, as pbrt-v4 types it: `"float fov" [ 45 ]`, `"rgb Kd" [ .5
//! .5 .5 ]`, `"spectrum eta" "metal-Cu-eta"`, `"blackbody L" [ 3000 ]`, `"texture
//! reflectance" "name"`, `"bool twosided" true`, `"string filename" "a.ply"`, `"point3 P"`,
//! `"normal N"`, `"point2 uv"`, `"integer indices"` (and pbrt-v3's spellings `point`,
//! `vector`, `normal3`, `color`). A single value may go without brackets. Every parameter
//! must be read by the directive that owns it: [`Params::finish`] refuses any left over, as
//! pbrt-v4 does ("unused parameter").

use super::super::SceneError;
use super::lexer::{Tok, Token};
use super::spectra::{self, SpectrumUse};
use glam::Vec3;
use std::cell::Cell;
use std::path::{Path, PathBuf};
use std::rc::Rc;

type Result<T> = std::result::Result<T, SceneError>;

/// One value of a parameter.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Num(f64),
    Str(String),
    Bool(bool),
}

/// One typed parameter.
#[derive(Clone, Debug)]
pub struct Param {
    /// Its type, pbrt-v3's spellings mapped to pbrt-v4's (`point` is `point3`).
    pub ty: String,
    pub name: String,
    pub values: Vec<Value>,
    pub line: usize,
    used: Cell<bool>,
}

/// A parameter list: the file and line of its directive, and its parameters.
#[derive(Clone, Debug)]
pub struct Params {
    pub file: Rc<PathBuf>,
    /// The directory relative file names are resolved against (the scene file's).
    pub dir: Rc<PathBuf>,
    /// The directive and its type (`Shape "sphere"`), for messages.
    pub what: String,
    pub line: usize,
    pub list: Vec<Param>,
}

/// A spectrum-valued parameter: a colour, or a named texture.
#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    Rgb(Vec3),
    Texture(String),
}

/// A float-valued parameter that may be textured.
#[derive(Clone, Debug, PartialEq)]
pub enum FloatParam {
    Const(f32),
    Texture(String),
}

const TYPES: &[&str] = &[
    "integer",
    "float",
    "point2",
    "vector2",
    "point3",
    "vector3",
    "normal",
    "spectrum",
    "rgb",
    "blackbody",
    "bool",
    "string",
    "texture",
];

impl Params {
    /// Reads the parameters at `tokens[*i..]`: each a quoted `"type name"` and its values.
    pub fn parse(
        tokens: &[Token],
        i: &mut usize,
        file: &Rc<PathBuf>,
        dir: &Rc<PathBuf>,
        what: String,
        line: usize,
    ) -> Result<Params> {
        let mut list: Vec<Param> = Vec::new();
        while let Some(Token { tok: Tok::Str(decl), line: at }) = tokens.get(*i) {
            let at = *at;
            let err = |m: String| SceneError::new(file, Some(at), None, m);
            let words: Vec<&str> = decl.split_whitespace().collect();
            let [ty, name] = words.as_slice() else {
                return Err(err(format!("\"{decl}\": a parameter is declared as \"type name\"")));
            };
            let ty = match *ty {
                "point" => "point3",
                "vector" => "vector3",
                "normal3" => "normal",
                "color" => "rgb",
                t => t,
            };
            if !TYPES.contains(&ty) {
                return Err(SceneError::new(file, Some(at), Some(name), format!("\"{ty}\": unknown parameter type")));
            }
            if list.iter().any(|p| p.name == *name) {
                return Err(SceneError::new(file, Some(at), Some(name), format!("\"{name}\": parameter given twice")));
            }
            *i += 1;
            let mut values = Vec::new();
            let mut one = |t: &Token| -> Result<()> {
                values.push(match &t.tok {
                    Tok::Word(w) if w == "true" => Value::Bool(true),
                    Tok::Word(w) if w == "false" => Value::Bool(false),
                    Tok::Word(w) => Value::Num(
                        w.parse::<f64>()
                            .map_err(|_| SceneError::new(file, Some(t.line), Some(name), format!("`{w}` is not a number")))?,
                    ),
                    Tok::Str(s) if ty == "bool" && (s == "true" || s == "false") => Value::Bool(s == "true"),
                    Tok::Str(s) => Value::Str(s.clone()),
                    _ => unreachable!(),
                });
                Ok(())
            };
            match tokens.get(*i) {
                Some(Token { tok: Tok::Open, .. }) => {
                    *i += 1;
                    loop {
                        match tokens.get(*i) {
                            Some(Token { tok: Tok::Close, .. }) => break,
                            Some(t @ Token { tok: Tok::Word(_) | Tok::Str(_), .. }) => one(t)?,
                            _ => return Err(err(format!("\"{decl}\": the values' `[` is not closed by `]`"))),
                        }
                        *i += 1;
                    }
                    *i += 1;
                }
                Some(t @ Token { tok: Tok::Word(_) | Tok::Str(_), .. }) => {
                    one(t)?;
                    *i += 1;
                }
                _ => return Err(err(format!("\"{decl}\": the parameter has no value"))),
            }
            let kind_ok = |v: &Value| match ty {
                "bool" => matches!(v, Value::Bool(_)),
                "string" | "texture" => matches!(v, Value::Str(_)),
                "spectrum" => !matches!(v, Value::Bool(_)),
                _ => matches!(v, Value::Num(_)),
            };
            if let Some(v) = values.iter().find(|v| !kind_ok(v)) {
                return Err(SceneError::new(file, Some(at), Some(name), format!("{v:?} is not a value of a {ty} parameter")));
            }
            if values.is_empty() {
                return Err(SceneError::new(file, Some(at), Some(name), format!("\"{name}\": no values")));
            }
            list.push(Param { ty: ty.to_owned(), name: (*name).to_owned(), values, line: at, used: Cell::new(false) });
        }
        Ok(Params { file: file.clone(), dir: dir.clone(), what, line, list })
    }

    /// The parameter `name`, marked read.
    pub fn get(&self, name: &str) -> Option<&Param> {
        let p = self.list.iter().find(|p| p.name == name)?;
        p.used.set(true);
        Some(p)
    }

    /// Whether `name` is given.
    pub fn has(&self, name: &str) -> bool {
        self.list.iter().any(|p| p.name == name)
    }

    /// An error about parameter `name`, at its line where given, else the directive's.
    pub fn error(&self, name: &str, message: impl Into<String>) -> SceneError {
        let line = self.list.iter().find(|p| p.name == name).map_or(self.line, |p| p.line);
        SceneError::new(&self.file, Some(line), Some(name), message)
    }

    /// An error about the directive itself.
    pub fn directive_error(&self, message: impl Into<String>) -> SceneError {
        SceneError::new(&self.file, Some(self.line), Some(&self.what), message)
    }

    /// The parameter `name` of one of `types`, or an error when it has another.
    fn typed(&self, name: &str, types: &[&str]) -> Result<Option<&Param>> {
        let Some(p) = self.get(name) else { return Ok(None) };
        if !types.contains(&p.ty.as_str()) {
            return Err(
                self.error(name, format!("\"{name}\" is given as {}; {} takes it as {}", p.ty, self.what, types.join(" or ")))
            );
        }
        Ok(Some(p))
    }

    /// The numbers of `name` (of type `ty`), each finite.
    pub fn numbers(&self, name: &str, ty: &str) -> Result<Option<Vec<f64>>> {
        let Some(p) = self.typed(name, &[ty])? else { return Ok(None) };
        let v: Vec<f64> = p.values.iter().map(|v| if let Value::Num(x) = v { *x } else { f64::NAN }).collect();
        if v.iter().any(|x| !x.is_finite()) {
            return Err(self.error(name, format!("\"{name}\": every value must be a finite number")));
        }
        Ok(Some(v))
    }

    /// A single number of `name` (of type `ty`).
    fn one(&self, name: &str, ty: &str) -> Result<Option<f64>> {
        match self.numbers(name, ty)? {
            None => Ok(None),
            Some(v) if v.len() == 1 => Ok(Some(v[0])),
            Some(v) => Err(self.error(name, format!("\"{name}\" takes one value, found {}", v.len()))),
        }
    }

    pub fn float(&self, name: &str) -> Result<Option<f32>> {
        Ok(self.one(name, "float")?.map(|x| x as f32))
    }

    pub fn float_or(&self, name: &str, default: f32) -> Result<f32> {
        Ok(self.float(name)?.unwrap_or(default))
    }

    pub fn int(&self, name: &str) -> Result<Option<i64>> {
        match self.one(name, "integer")? {
            Some(x) if x.fract() != 0.0 || x.abs() > 2f64.powi(53) => {
                Err(self.error(name, format!("\"{name}\": {x} is not an integer")))
            }
            x => Ok(x.map(|x| x as i64)),
        }
    }

    pub fn int_or(&self, name: &str, default: i64) -> Result<i64> {
        Ok(self.int(name)?.unwrap_or(default))
    }

    pub fn bool_or(&self, name: &str, default: bool) -> Result<bool> {
        let Some(p) = self.typed(name, &["bool"])? else { return Ok(default) };
        match p.values.as_slice() {
            [Value::Bool(b)] => Ok(*b),
            _ => Err(self.error(name, format!("\"{name}\" takes one bool"))),
        }
    }

    pub fn string(&self, name: &str) -> Result<Option<&str>> {
        let Some(p) = self.typed(name, &["string"])? else { return Ok(None) };
        match p.values.as_slice() {
            [Value::Str(s)] => Ok(Some(s)),
            _ => Err(self.error(name, format!("\"{name}\" takes one string"))),
        }
    }

    /// A list of strings (`"string materials" [ "a" "b" ]`).
    pub fn strings(&self, name: &str) -> Result<Option<Vec<String>>> {
        let Some(p) = self.typed(name, &["string"])? else { return Ok(None) };
        let strings: Option<Vec<String>> =
            p.values.iter().map(|v| if let Value::Str(s) = v { Some(s.clone()) } else { None }).collect();
        strings.map(Some).ok_or_else(|| self.error(name, format!("\"{name}\" takes strings")))
    }

    /// A texture's name (`"texture name" "tex"`).
    pub fn texture(&self, name: &str) -> Result<Option<&str>> {
        let Some(p) = self.typed(name, &["texture"])? else { return Ok(None) };
        match p.values.as_slice() {
            [Value::Str(s)] => Ok(Some(s)),
            _ => Err(self.error(name, format!("\"{name}\" names one texture"))),
        }
    }

    /// Points of `name` (of type `ty`, `n` numbers each).
    pub fn points<const N: usize>(&self, name: &str, ty: &str) -> Result<Option<Vec<[f32; N]>>> {
        let Some(v) = self.numbers(name, ty)? else { return Ok(None) };
        if v.len() % N != 0 {
            return Err(self.error(name, format!("\"{name}\": {} values is not a whole number of {ty}s", v.len())));
        }
        Ok(Some(v.chunks(N).map(|c| std::array::from_fn(|k| c[k] as f32)).collect()))
    }

    /// A point3 (or vector3) parameter of one point.
    pub fn point3(&self, name: &str, ty: &str) -> Result<Option<Vec3>> {
        match self.points::<3>(name, ty)? {
            None => Ok(None),
            Some(v) if v.len() == 1 => Ok(Some(Vec3::from(v[0]))),
            Some(_) => Err(self.error(name, format!("\"{name}\" takes one {ty}"))),
        }
    }

    /// A float parameter that may be a texture.
    pub fn float_texture(&self, name: &str) -> Result<Option<FloatParam>> {
        if let Some(t) = self.list.iter().find(|p| p.name == name && p.ty == "texture") {
            let _ = t;
            return Ok(self.texture(name)?.map(|s| FloatParam::Texture(s.to_owned())));
        }
        Ok(self.float(name)?.map(FloatParam::Const))
    }

    /// A spectrum parameter (`rgb`, `spectrum`, `blackbody`, a `float` for a constant, or a
    /// `texture`) as linear RGB for its use, or the texture's name.
    pub fn spectrum(&self, name: &str, used: SpectrumUse) -> Result<Option<Spectrum>> {
        let Some(p) = self.typed(name, &["rgb", "spectrum", "blackbody", "float", "texture"])? else { return Ok(None) };
        let nums = || p.values.iter().map(|v| if let Value::Num(x) = v { *x as f32 } else { f32::NAN }).collect::<Vec<_>>();
        let rgb = match p.ty.as_str() {
            "texture" => return Ok(self.texture(name)?.map(|s| Spectrum::Texture(s.to_owned()))),
            "float" => Vec3::splat(self.float(name)?.unwrap()),
            "rgb" => match nums().as_slice() {
                &[r, g, b] if r.is_finite() && g.is_finite() && b.is_finite() => {
                    let rgb = Vec3::new(r, g, b);
                    if used == SpectrumUse::Albedo && (rgb.min_element() < 0.0 || rgb.max_element() > 1.0) {
                        return Err(self.error(name, format!("\"{name}\": reflectance {rgb} is outside [0, 1]")));
                    }
                    if rgb.min_element() < 0.0 {
                        return Err(self.error(name, format!("\"{name}\": {rgb} is negative")));
                    }
                    rgb
                }
                v => return Err(self.error(name, format!("\"{name}\": an rgb value is three finite numbers, found {}", v.len()))),
            },
            "blackbody" => match nums().as_slice() {
                &[t] if t.is_finite() && t > 0.0 => spectra::blackbody_rgb(t, used),
                _ => return Err(self.error(name, format!("\"{name}\": a blackbody is one temperature in kelvin, above 0"))),
            },
            _ => match p.values.as_slice() {
                [Value::Str(s)] => spectra::named_or_file(s, used, &|n| self.resolve(n)).map_err(|e| self.error(name, e))?,
                values => {
                    let v = nums();
                    if v.len() < 4 || v.len() % 2 != 0 || v.iter().any(|x| !x.is_finite()) || values.len() != v.len() {
                        return Err(self.error(
                            name,
                            format!("\"{name}\": a spectrum is a name, a file, or pairs of wavelength (nm) and value"),
                        ));
                    }
                    let points: Vec<(f32, f32)> = v.chunks(2).map(|c| (c[0], c[1])).collect();
                    spectra::sampled_rgb(&points, used).map_err(|e| self.error(name, e))?
                }
            },
        };
        Ok(Some(Spectrum::Rgb(rgb)))
    }

    /// The file `name` names: relative to the scene file's directory, as pbrt-v4 resolves
    /// every file name, or else to the directory of the file that names it (an included one).
    pub fn resolve(&self, name: &str) -> PathBuf {
        resolve(&self.dir, &self.file, name)
    }

    /// Marks `names` read: parameters pbrt-v4 reads that change only the noise or the speed.
    pub fn pass_over(&self, names: &[&str]) {
        for name in names {
            self.get(name);
        }
    }

    /// Refuses the first parameter not read, as pbrt-v4 refuses it.
    pub fn finish(&self) -> Result<()> {
        match self.list.iter().find(|p| !p.used.get()) {
            Some(p) => Err(self.error(&p.name, format!("\"{}\": unused parameter ({} does not take it)", p.name, self.what))),
            None => Ok(()),
        }
    }
}

/// The file `name` names, from `file`: relative to `dir` (the scene file's directory), as
/// pbrt-v4 resolves every file name, or else to `file`'s directory where only that has it.
pub fn resolve(dir: &Path, file: &Path, name: &str) -> PathBuf {
    let path = dir.join(name);
    let beside = file.parent().unwrap_or(Path::new("")).join(name);
    if !path.exists() && beside.exists() {
        return beside;
    }
    path
}
