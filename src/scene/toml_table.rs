//! TOML tables: the reader's, walked by hand so that every key and value keeps its line for
//! error messages (a table checks its keys, [`Table::allow_keys`] and [`Table::typed`], a value
//! its type, [`Value::f32_in`], [`Value::rgb`]), and the writer's keys (`convert`). The readers
//! of the scene file (`load.rs`) and of each model (`material/`, `emitter/`) stand on them.

use super::param::{out_of, Bound, Invalid};
use super::{Medium, SceneError};
use glam::{Vec2, Vec3};
use std::path::{Path, PathBuf};
use toml::de::{DeInteger, DeString, DeTable, DeValue};
use toml::Spanned;

type Result<T> = std::result::Result<T, SceneError>;

/// The scene file: its name and where its lines start.
pub(super) struct Source<'a> {
    pub(super) path: &'a Path,
    /// Byte offset of the start of each line.
    pub(super) line_starts: Vec<usize>,
}

impl<'a> Source<'a> {
    pub(super) fn new(text: &str, path: &'a Path) -> Self {
        let line_starts = std::iter::once(0).chain(text.match_indices('\n').map(|(i, _)| i + 1)).collect();
        Source { path, line_starts }
    }

    /// The 1-based line holding byte `offset`.
    pub(super) fn line(&self, offset: usize) -> usize {
        self.line_starts.partition_point(|&start| start <= offset)
    }

    pub(super) fn error(&self, line: Option<usize>, key: Option<&str>, message: impl Into<String>) -> SceneError {
        SceneError::new(self.path, line, key, message)
    }
}

/// A TOML table of the scene, with its dotted key (empty for the document) and the line of
/// its header or inline table (none for the document).
pub(super) struct Table<'a, 'i> {
    pub(super) source: &'a Source<'a>,
    pub(super) table: &'a DeTable<'i>,
    pub(super) key: String,
    pub(super) line: Option<usize>,
}

impl<'a, 'i> Table<'a, 'i> {
    pub(super) fn child_key(&self, name: &str) -> String {
        if self.key.is_empty() {
            name.to_owned()
        } else {
            format!("{}.{name}", self.key)
        }
    }

    /// The entries with their names, in file order.
    pub(super) fn entries(&self) -> Vec<(&'a str, Value<'a, 'i>)> {
        let mut entries: Vec<_> = self.table.iter().collect();
        entries.sort_by_key(|(name, _)| name.span().start);
        entries.into_iter().map(|(name, value)| self.entry(name, value)).collect()
    }

    pub(super) fn get(&self, name: &str) -> Option<Value<'a, 'i>> {
        let (name, value) = self.table.get_key_value(name)?;
        Some(self.entry(name, value).1)
    }

    /// An entry's name, and its value at the line of its key.
    pub(super) fn entry(&self, name: &'a Spanned<DeString<'i>>, value: &'a Spanned<DeValue<'i>>) -> (&'a str, Value<'a, 'i>) {
        let value = Value {
            source: self.source,
            value: value.get_ref(),
            key: self.child_key(name.get_ref()),
            line: self.source.line(name.span().start),
        };
        (name.get_ref().as_ref(), value)
    }

    /// An error about the table itself, at its header's line.
    pub(super) fn error_here(&self, message: impl Into<String>) -> SceneError {
        self.source.error(self.line, Some(&self.key), message)
    }

    /// An error about key `name`: at its line when it is present, else at the header's.
    pub(super) fn error_at(&self, name: &str, message: impl Into<String>) -> SceneError {
        let line = self.get(name).map(|v| v.line).or(self.line);
        self.source.error(line, Some(&self.child_key(name)), message)
    }

    /// The error for a parameter that a model's check refuses: at the line of the channel that
    /// is out, where the value is an array over lines, else at the key's.
    pub(super) fn invalid(&self, e: Invalid) -> SceneError {
        let item = e.channel.zip(self.get(e.key)).and_then(|(i, v)| v.elements().ok()?.into_iter().nth(i));
        match item {
            Some(item) => self.source.error(Some(item.line), Some(&self.child_key(e.key)), e.message),
            None => self.error_at(e.key, e.message),
        }
    }

    pub(super) fn require(&self, name: &str) -> Result<Value<'a, 'i>> {
        self.get(name).ok_or_else(|| self.error_at(name, format!("missing required key `{name}`")))
    }

    /// Reads the required key `name` with `read`.
    pub(super) fn req<T>(&self, name: &str, read: impl FnOnce(&Value<'a, 'i>) -> Result<T>) -> Result<T> {
        read(&self.require(name)?)
    }

    /// Reads the key `name` with `read` when it is present.
    pub(super) fn opt<T>(&self, name: &str, read: impl FnOnce(&Value<'a, 'i>) -> Result<T>) -> Result<Option<T>> {
        self.get(name).map(|v| read(&v)).transpose()
    }

    /// Reads the key `name` with `read`, or gives `default` when it is absent.
    pub(super) fn or<T>(&self, name: &str, default: T, read: impl FnOnce(&Value<'a, 'i>) -> Result<T>) -> Result<T> {
        Ok(self.opt(name, read)?.unwrap_or(default))
    }

    /// Fails on the first key (in file order) that is not in `allowed`.
    pub(super) fn allow_keys(&self, allowed: &[&str]) -> Result<()> {
        match self.entries().into_iter().find(|(name, _)| !allowed.contains(name)) {
            Some((name, value)) => Err(value.error(format!("unknown key `{name}`; allowed keys: {}", allowed.join(", ")))),
            None => Ok(()),
        }
    }

    /// Reads `type` as one of `types` (`what` names them in errors), then allows only the
    /// `common` keys and that type's own.
    pub(super) fn typed<T: Copy>(&self, what: &str, types: &[(&str, T, &[&str])], common: &[&str]) -> Result<T> {
        let names: Vec<(&str, usize)> = types.iter().enumerate().map(|(i, t)| (t.0, i)).collect();
        let (_, kind, keys) = types[self.req("type", |v| v.choice(what, &names))?];
        self.allow_keys(&[common, keys].concat())?;
        Ok(kind)
    }
}

/// A TOML value of the scene with its dotted key and line.
pub(super) struct Value<'a, 'i> {
    pub(super) source: &'a Source<'a>,
    pub(super) value: &'a DeValue<'i>,
    pub(super) key: String,
    pub(super) line: usize,
}

impl<'a, 'i> Value<'a, 'i> {
    pub(super) fn error(&self, message: impl Into<String>) -> SceneError {
        self.source.error(Some(self.line), Some(&self.key), message)
    }

    /// A type error: `what` was expected.
    pub(super) fn expected(&self, what: &str) -> SceneError {
        let found = match self.value {
            DeValue::String(_) => "a string",
            DeValue::Integer(_) => "an integer",
            DeValue::Float(_) => "a float",
            DeValue::Boolean(_) => "a boolean",
            DeValue::Datetime(_) => "a date-time",
            DeValue::Array(_) => "an array",
            DeValue::Table(_) => "a table",
        };
        self.error(format!("expected {what}, found {found}"))
    }

    pub(super) fn table(&self) -> Result<Table<'a, 'i>> {
        match self.value {
            DeValue::Table(table) => Ok(Table { source: self.source, table, key: self.key.clone(), line: Some(self.line) }),
            _ => Err(self.expected("a table")),
        }
    }

    /// The items of an array, keyed `key[i]`, each at its own line.
    pub(super) fn elements(&self) -> Result<Vec<Value<'a, 'i>>> {
        let DeValue::Array(items) = self.value else {
            return Err(self.expected("an array"));
        };
        let element = |(i, item): (usize, &'a Spanned<DeValue<'i>>)| Value {
            source: self.source,
            value: item.get_ref(),
            key: format!("{}[{i}]", self.key),
            line: self.source.line(item.span().start),
        };
        Ok(items.iter().enumerate().map(element).collect())
    }

    pub(super) fn string(&self) -> Result<&'a str> {
        self.value.as_str().ok_or_else(|| self.expected("a string"))
    }

    pub(super) fn bool(&self) -> Result<bool> {
        self.value.as_bool().ok_or_else(|| self.expected("a boolean (true or false)"))
    }

    /// A setting's name, from its [`Named`] table.
    pub(super) fn named<T: super::Named>(&self) -> Result<T> {
        T::from_name(self.string()?).map_err(|e| self.error(e))
    }

    /// A string that must name one of `options`; `what` names it in errors.
    pub(super) fn choice<T: Copy>(&self, what: &str, options: &[(&str, T)]) -> Result<T> {
        let name = self.string()?;
        match options.iter().find(|(option, _)| *option == name) {
            Some(&(_, value)) => Ok(value),
            None => {
                let names: Vec<&str> = options.iter().map(|(option, _)| *option).collect();
                Err(self.error(format!("unknown {what} `{name}`; expected one of: {}", names.join(", "))))
            }
        }
    }

    /// An integer in `min..=max`.
    pub(super) fn u32_in(&self, min: u32, max: u32) -> Result<u32> {
        let integer = match self.value {
            DeValue::Integer(integer) => integer,
            DeValue::Float(float) => return Err(self.error(format!("expected an integer, found the float {float}"))),
            _ => return Err(self.expected("an integer")),
        };
        if !has_digits(integer) {
            return Err(self.error(format!("`{integer}` is not a valid integer: it has no digits")));
        }
        parse_integer(integer)
            .and_then(|n| u32::try_from(n).ok())
            .filter(|n| (min..=max).contains(n))
            .ok_or_else(|| self.error(format!("must be between {min} and {max}, found {integer}")))
    }

    /// A count of at least 1.
    pub(super) fn count(&self) -> Result<u32> {
        self.u32_in(1, u32::MAX)
    }

    /// A number, integer or float, unchecked.
    pub(super) fn number(&self) -> Result<f64> {
        let number = match self.value {
            DeValue::Integer(integer) if !has_digits(integer) => {
                return Err(self.error(format!("`{integer}` is not a valid integer: it has no digits")))
            }
            DeValue::Integer(integer) => parse_integer(integer).map(|n| n as f64),
            DeValue::Float(float) => float.as_str().parse().ok(),
            _ => return Err(self.expected("a number")),
        };
        number.ok_or_else(|| match self.value {
            DeValue::Integer(integer) => {
                self.error(format!("{integer} is beyond the range of 64-bit integers; write it as a float"))
            }
            _ => self.error(format!("`{}` is not a valid number", self.literal())),
        })
    }

    /// A number as written in the file, for messages.
    pub(super) fn literal(&self) -> String {
        match self.value {
            DeValue::Integer(integer) => integer.to_string(),
            DeValue::Float(float) => float.to_string(),
            other => other.type_str().to_owned(),
        }
    }

    pub(super) fn f64_in(&self, bound: Bound) -> Result<f64> {
        let x = self.number()?;
        match out_of(x, &self.literal(), bound) {
            Some(why) => Err(self.error(why)),
            None => Ok(x),
        }
    }

    pub(super) fn f32_in(&self, bound: Bound) -> Result<f32> {
        let x = self.f64_in(bound)? as f32;
        // Rounding may overflow, or underflow to a zero that `bound` rejects.
        if x.is_infinite() || !bound.contains(x.into()) {
            let message = format!("{} is out of the range of 32-bit floats", self.literal());
            return Err(self.error(message));
        }
        Ok(x)
    }

    /// An array of `N` numbers, each finite and within `bound`.
    pub(super) fn floats<const N: usize>(&self, bound: Bound) -> Result<[f32; N]> {
        let what = format!("an array of {N} numbers");
        let items = self.elements().map_err(|_| self.expected(&what))?;
        if items.len() != N {
            return Err(self.error(format!("expected {what}, found {} items", items.len())));
        }
        let mut out = [0.0; N];
        for (x, item) in out.iter_mut().zip(items) {
            // Errors name the array's key, at the item's line.
            *x = Value { key: self.key.clone(), ..item }.f32_in(bound)?;
        }
        Ok(out)
    }

    pub(super) fn vec2_in(&self, bound: Bound) -> Result<Vec2> {
        self.floats(bound).map(Vec2::from_array)
    }

    pub(super) fn vec3_in(&self, bound: Bound) -> Result<Vec3> {
        self.floats(bound).map(Vec3::from_array)
    }

    pub(super) fn vec3(&self) -> Result<Vec3> {
        self.vec3_in(Bound::Any)
    }

    /// A colour (every colour-valued key): one number (grey) or `[r, g, b]`, each within
    /// `bound`.
    pub(super) fn rgb(&self, bound: Bound) -> Result<Vec3> {
        match self.value {
            DeValue::Array(_) => self.vec3_in(bound),
            DeValue::Integer(_) | DeValue::Float(_) => self.f32_in(bound).map(Vec3::splat),
            _ => Err(self.expected("one number or an array of 3 numbers")),
        }
    }

    /// The index of the medium this value names (`[media.<name>]`).
    pub(super) fn medium(&self, media: &[Medium]) -> Result<u32> {
        let name = self.string()?;
        if let Some(index) = media.iter().position(|m| m.name == name) {
            return Ok(index as u32);
        }
        let names: Vec<&str> = media.iter().map(|m| m.name.as_str()).collect();
        let defined = if names.is_empty() {
            "no media are defined (a [media.<name>] table defines one)".to_owned()
        } else {
            format!("defined media: {}", names.join(", "))
        };
        Err(self.error(format!("unknown medium `{name}`; {defined}")))
    }

    /// A scale: one number or three, each nonzero.
    pub(super) fn scale(&self) -> Result<Vec3> {
        match self.value {
            DeValue::Array(_) => self.vec3_in(Bound::NonZero),
            _ => self.f32_in(Bound::NonZero).map(Vec3::splat),
        }
    }

    /// A path relative to the scene file's directory.
    pub(super) fn path(&self) -> Result<PathBuf> {
        let directory = self.source.path.parent().unwrap_or(Path::new(""));
        Ok(directory.join(self.string()?))
    }

    /// Reads the `what` file at `path` (which this value names) with `read`.
    pub(super) fn read_file<T>(&self, what: &str, path: &Path, read: fn(&Path) -> std::result::Result<T, String>) -> Result<T> {
        read(path).map_err(|e| self.error(format!("cannot read {what} {}: {e}", path.display())))
    }
}

/// A TOML integer (any radix), when it fits in an `i64`.
fn parse_integer(integer: &DeInteger) -> Option<i64> {
    i64::from_str_radix(integer.as_str(), integer.radix()).ok()
}

/// Whether a TOML integer has digits at all (`0x` alone has none); one that has them and
/// still does not parse is beyond the 64-bit range.
fn has_digits(integer: &DeInteger) -> bool {
    integer.as_str().trim_start_matches(['+', '-']).chars().any(|c| c.is_digit(integer.radix()))
}

/// Writes `key = value` (a string) in a TOML table being written.
pub(super) fn put_str(t: &mut toml::Table, key: &str, value: &str) {
    t.insert(key.into(), toml::Value::String(value.into()));
}

/// Writes `key = x`.
pub(super) fn put_float(t: &mut toml::Table, key: &str, x: f32) {
    t.insert(key.into(), toml::Value::Float(x as f64));
}

/// Writes `key = [x, y, z]`.
pub(super) fn put_vec3(t: &mut toml::Table, key: &str, v: Vec3) {
    t.insert(key.into(), toml::Value::Array(v.to_array().iter().map(|&x| toml::Value::Float(x as f64)).collect()));
}
