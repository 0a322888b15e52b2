//! The plain shape of a TOML scene file read in one pass, without the document
//! tree the `toml` crate builds before serde reads it.
//!
//! The plain shape is what scene files hold: an optional `clearance = number` at the top, then
//! `[[obstacles]]` sections of `key = value` lines with the fields of [`FileObstacle`] (each at
//! most once), whose values are strings, numbers, arrays of 3 or 4 numbers, or (`rotation`) an
//! inline table of one key `rpy` or `quaternion`. Comments, whitespace, quoted keys, literal and
//! escaped strings, underscores in numbers and multi-line arrays are all read.
//!
//! The syntax is the `toml` crate's own: its lexer and event parser (`toml_parser`, the crate
//! `toml` itself parses with), its whitespace and comment checks, and its scalar decoding; only
//! the step from events to [`FileScene`] is here. Numbers become `f64` as `toml` + serde make
//! them: a float is `str::parse::<f64>` of the decoded text (refused when it overflows to an
//! infinity without being written `inf`, as `toml` refuses it), a decimal integer is
//! `i64::from_str_radix(…, 10)` (which `str::parse::<i64>` is) then `as f64` (serde's
//! integer-to-float conversion).
//!
//! Anything else — a syntax error, a dotted key, a `[table]`, another array of tables, a
//! repeated or unknown key, a value of another type or length, a missing `shape`, a date, a
//! hexadecimal or out-of-range integer — gives `None`, and the caller reads the text with
//! `toml::from_str` instead, so every message, and every file outside the plain shape, is
//! exactly what `toml` gives. The rule that makes this safe: when this reader gives a scene,
//! `toml::from_str` gives the same one (tests below, on every TOML file in `models/`, the
//! generated scenes and their variants).

use super::{FileObstacle, FileRotation, FileScale, FileScene};
use std::borrow::Cow;
use toml_parser::decoder::{Encoding, IntegerRadix, ScalarKind};
use toml_parser::parser::{EventReceiver, ValidateWhitespace};
use toml_parser::{ErrorSink, ParseError, Raw, Source, Span};

/// The scene in `text` when it has the plain shape (module doc), else `None`.
pub(super) fn plain_scene(text: &str) -> Option<FileScene> {
    let source = Source::new(text);
    let tokens = source.lex().into_vec();
    let mut reader = Reader::new(text);
    let mut failed = Failed(false);
    {
        let mut checked = ValidateWhitespace::new(&mut reader, source);
        toml_parser::parser::parse_document(&tokens, &mut checked, &mut failed);
    }
    if failed.0 {
        return None;
    }
    reader.finish()
}

/// The value of a number written plainly, `-?(0|[1-9][0-9]*)(\.[0-9]+)?([eE][+-]?[0-9]+)?`
/// (no `+`, no underscores), as the decoder path of [`Reader::number`] gives it: every such
/// text is a valid TOML integer (without fraction and exponent) or float that decodes to
/// itself, so the same `str::parse::<i64>` then `as f64`, or `str::parse::<f64>` (finite:
/// it is not written `inf`), of the same text. `None` for any other text, which then goes through
/// the decoder.
fn plain_number(s: &str) -> Option<f64> {
    let b = s.as_bytes();
    let digits = |i: &mut usize| {
        let start = *i;
        while b.get(*i).is_some_and(u8::is_ascii_digit) {
            *i += 1;
        }
        *i - start
    };
    let mut i = usize::from(b.first() == Some(&b'-'));
    let first = b.get(i).copied();
    let n = digits(&mut i);
    if n == 0 || (n > 1 && first == Some(b'0')) {
        return None;
    }
    let mut float = false;
    if b.get(i) == Some(&b'.') {
        i += 1;
        if digits(&mut i) == 0 {
            return None;
        }
        float = true;
    }
    if matches!(b.get(i), Some(b'e' | b'E')) {
        i += 1;
        if matches!(b.get(i), Some(b'+' | b'-')) {
            i += 1;
        }
        if digits(&mut i) == 0 {
            return None;
        }
        float = true;
    }
    if i != b.len() {
        None
    } else if float {
        s.parse::<f64>().ok().filter(|f| f.is_finite())
    } else {
        s.parse::<i64>().ok().map(|i| i as f64)
    }
}

/// Records that the parser or a decoder reported an error (the message is `toml`'s to give).
struct Failed(bool);

impl ErrorSink for Failed {
    fn report_error(&mut self, _error: ParseError) {
        self.0 = true;
    }
}

/// The keys the plain shape knows: `clearance` at the top, the others in an obstacle.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Key {
    Clearance,
    Name,
    Shape,
    Position,
    Rotation,
    Radius,
    HalfExtents,
    HalfHeight,
    Path,
    Scale,
}

impl Key {
    /// The key named `name` in a table (`top`: the file's top level, else an obstacle).
    fn of(name: &str, top: bool) -> Option<Key> {
        Some(match (top, name) {
            (true, "clearance") => Key::Clearance,
            (false, "name") => Key::Name,
            (false, "shape") => Key::Shape,
            (false, "position") => Key::Position,
            (false, "rotation") => Key::Rotation,
            (false, "radius") => Key::Radius,
            (false, "half_extents") => Key::HalfExtents,
            (false, "half_height") => Key::HalfHeight,
            (false, "path") => Key::Path,
            (false, "scale") => Key::Scale,
            _ => return None,
        })
    }
}

/// A value as written: a number, a string, up to 4 numbers in an array, or `{ rpy | quaternion
/// = [numbers] }` (`true` for the quaternion).
enum Value<'i> {
    Number(f64),
    Text(Cow<'i, str>),
    Numbers([f64; 4], usize),
    Rotation(bool, [f64; 4], usize),
}

/// Where the event stream stands inside a `key = value` line.
#[derive(Clone, Copy, PartialEq)]
enum At {
    /// Between lines, or a table header's key.
    Line,
    /// After the key, before `=`.
    Key,
    /// After `=`, before the value.
    Value,
    /// Inside `[ … ]` of a top-level value.
    Array,
    /// Inside `{ … }`: before its key, after its key, after its `=`, inside its array, after it.
    InlineKey,
    InlineSep(bool),
    InlineValue(bool),
    InlineArray(bool),
    InlineDone(bool),
}

/// Builds the [`FileScene`] from parser events; `off` once the text leaves the plain shape.
struct Reader<'i> {
    text: &'i str,
    off: bool,
    scene: FileScene,
    /// The obstacle being read (after its `[[obstacles]]`), with a bit per key given.
    obstacle: Option<FileObstacle>,
    given: u16,
    /// Inside `[[ … ]]`, and whether its key (`obstacles`) was read.
    header: Option<bool>,
    at: At,
    key: Key,
    numbers: [f64; 4],
    count: usize,
}

impl<'i> Reader<'i> {
    fn new(text: &'i str) -> Self {
        Reader {
            text,
            off: false,
            scene: FileScene {
                clearance: None,
                obstacles: Vec::new(),
            },
            obstacle: None,
            given: 0,
            header: None,
            at: At::Line,
            key: Key::Clearance,
            numbers: [0.0; 4],
            count: 0,
        }
    }

    /// The scene, once every event is in: `None` when the text left the plain shape.
    fn finish(mut self) -> Option<FileScene> {
        if self.off || self.at != At::Line || self.header.is_some() {
            return None;
        }
        self.end_obstacle();
        (!self.off).then_some(self.scene)
    }

    /// The source text of `span`, read with `encoding` (quoted or not).
    fn raw(&self, span: Span, encoding: Option<Encoding>) -> Option<Raw<'i>> {
        let s = self.text.get(span.start()..span.end())?;
        Some(Raw::new_unchecked(s, encoding, span))
    }

    /// A number scalar as `toml` + serde turn it into an `f64` (module doc), else `None`. A
    /// number written plainly ([`plain_number`]) skips the decoder, which would only give back
    /// the same text (a third of the instructions of a large scene went to it).
    fn number(
        raw: Option<Raw<'i>>,
        encoding: Option<Encoding>,
        error: &mut dyn ErrorSink,
    ) -> Option<f64> {
        let raw = raw?;
        if encoding.is_none() {
            if let Some(x) = plain_number(raw.as_str()) {
                return Some(x);
            }
        }
        let mut decoded: Cow<'i, str> = Cow::Borrowed("");
        match raw.decode_scalar(&mut decoded, error) {
            ScalarKind::Float => {
                let f: f64 = decoded.parse().ok()?;
                (!f.is_infinite() || decoded.contains("inf")).then_some(f)
            }
            ScalarKind::Integer(IntegerRadix::Dec) => decoded.parse::<i64>().ok().map(|i| i as f64),
            _ => None,
        }
    }

    /// Closes the obstacle being read: it needs its `shape`, as `toml` + serde demand.
    fn end_obstacle(&mut self) {
        if let Some(o) = self.obstacle.take() {
            if self.given & (1 << Key::Shape as u16) != 0 {
                self.scene.obstacles.push(o);
            } else {
                self.off = true;
            }
        }
    }

    /// Stores `value` under the current key (top level or the obstacle being read).
    fn store(&mut self, value: Value<'i>) {
        self.at = At::Line;
        let three = |n: [f64; 4], c: usize| (c == 3).then(|| [n[0], n[1], n[2]]);
        let stored = match (self.obstacle.as_mut(), self.key, value) {
            (None, Key::Clearance, Value::Number(x)) => {
                self.scene.clearance = Some(x);
                Some(())
            }
            (Some(o), key, value) => match (key, value) {
                (Key::Name, Value::Text(s)) => {
                    o.name = Some(s.into_owned());
                    Some(())
                }
                (Key::Shape, Value::Text(s)) => {
                    o.shape = s.into_owned();
                    Some(())
                }
                (Key::Path, Value::Text(s)) => {
                    o.path = Some(s.into_owned());
                    Some(())
                }
                (Key::Radius, Value::Number(x)) => {
                    o.radius = Some(x);
                    Some(())
                }
                (Key::HalfHeight, Value::Number(x)) => {
                    o.half_height = Some(x);
                    Some(())
                }
                (Key::Position, Value::Numbers(n, c)) => three(n, c).map(|p| o.position = Some(p)),
                (Key::HalfExtents, Value::Numbers(n, c)) => {
                    three(n, c).map(|h| o.half_extents = Some(h))
                }
                (Key::Scale, Value::Number(x)) => {
                    o.scale = Some(FileScale::Uniform(x));
                    Some(())
                }
                (Key::Scale, Value::Numbers(n, c)) => {
                    three(n, c).map(|s| o.scale = Some(FileScale::PerAxis(s)))
                }
                (Key::Rotation, Value::Rotation(false, n, c)) => {
                    three(n, c).map(|r| o.rotation = Some(FileRotation::Rpy(r)))
                }
                (Key::Rotation, Value::Rotation(true, n, 4)) => {
                    o.rotation = Some(FileRotation::Quaternion(n));
                    Some(())
                }
                _ => None,
            },
            _ => None,
        };
        self.off |= stored.is_none();
    }

    /// One more number inside an array (at most 4).
    fn push_number(
        &mut self,
        raw: Option<Raw<'i>>,
        encoding: Option<Encoding>,
        error: &mut dyn ErrorSink,
    ) {
        match Self::number(raw, encoding, error) {
            Some(x) if self.count < 4 => {
                self.numbers[self.count] = x;
                self.count += 1;
            }
            _ => self.off = true,
        }
    }
}

impl EventReceiver for Reader<'_> {
    fn std_table_open(&mut self, _span: Span, _error: &mut dyn ErrorSink) {
        self.off = true;
    }
    fn std_table_close(&mut self, _span: Span, _error: &mut dyn ErrorSink) {
        self.off = true;
    }
    fn array_table_open(&mut self, _span: Span, _error: &mut dyn ErrorSink) {
        if self.at != At::Line || self.header.is_some() {
            self.off = true;
        }
        self.end_obstacle();
        self.header = Some(false);
    }
    fn array_table_close(&mut self, _span: Span, _error: &mut dyn ErrorSink) {
        if self.header != Some(true) {
            self.off = true;
        }
        self.header = None;
        self.obstacle = Some(FileObstacle {
            name: None,
            shape: String::new(),
            position: None,
            rotation: None,
            radius: None,
            half_extents: None,
            half_height: None,
            path: None,
            scale: None,
            free: None,
        });
        self.given = 0;
    }
    fn inline_table_open(&mut self, _span: Span, _error: &mut dyn ErrorSink) -> bool {
        if self.at == At::Value {
            self.at = At::InlineKey;
        } else {
            self.off = true;
        }
        !self.off
    }
    fn inline_table_close(&mut self, _span: Span, _error: &mut dyn ErrorSink) {
        match self.at {
            At::InlineDone(quaternion) => {
                self.store(Value::Rotation(quaternion, self.numbers, self.count))
            }
            _ => self.off = true,
        }
    }
    fn array_open(&mut self, _span: Span, _error: &mut dyn ErrorSink) -> bool {
        self.count = 0;
        match self.at {
            At::Value => self.at = At::Array,
            At::InlineValue(q) => self.at = At::InlineArray(q),
            _ => self.off = true,
        }
        !self.off
    }
    fn array_close(&mut self, _span: Span, _error: &mut dyn ErrorSink) {
        match self.at {
            At::Array => self.store(Value::Numbers(self.numbers, self.count)),
            At::InlineArray(q) => self.at = At::InlineDone(q),
            _ => self.off = true,
        }
    }
    fn simple_key(&mut self, span: Span, encoding: Option<Encoding>, error: &mut dyn ErrorSink) {
        let mut name: Cow<'_, str> = Cow::Borrowed("");
        match self.raw(span, encoding) {
            Some(raw) => raw.decode_key(&mut name, error),
            None => self.off = true,
        }
        match (self.header, self.at) {
            (Some(false), At::Line) if name == "obstacles" => self.header = Some(true),
            (None, At::Line) => match Key::of(name.as_ref(), self.obstacle.is_none()) {
                Some(key) if (self.given & (1 << key as u16)) == 0 => {
                    self.given |= 1 << key as u16;
                    self.key = key;
                    self.at = At::Key;
                }
                _ => self.off = true,
            },
            (None, At::InlineKey) if name == "rpy" || name == "quaternion" => {
                self.at = At::InlineSep(name == "quaternion")
            }
            _ => self.off = true,
        }
    }
    fn key_sep(&mut self, _span: Span, _error: &mut dyn ErrorSink) {
        self.off = true;
    }
    fn key_val_sep(&mut self, _span: Span, _error: &mut dyn ErrorSink) {
        match self.at {
            At::Key => self.at = At::Value,
            At::InlineSep(q) => self.at = At::InlineValue(q),
            _ => self.off = true,
        }
    }
    fn scalar(&mut self, span: Span, encoding: Option<Encoding>, error: &mut dyn ErrorSink) {
        let raw = self.raw(span, encoding);
        match self.at {
            At::Array | At::InlineArray(_) => self.push_number(raw, encoding, error),
            At::Value if encoding.is_some() => {
                let mut s: Cow<'_, str> = Cow::Borrowed("");
                match raw.map(|r| r.decode_scalar(&mut s, error)) {
                    Some(ScalarKind::String) => self.store(Value::Text(s)),
                    _ => self.off = true,
                }
            }
            At::Value => match Self::number(raw, encoding, error) {
                Some(x) => self.store(Value::Number(x)),
                None => self.off = true,
            },
            _ => self.off = true,
        }
    }
    fn value_sep(&mut self, _span: Span, _error: &mut dyn ErrorSink) {
        if !matches!(self.at, At::Array | At::InlineArray(_)) {
            self.off = true;
        }
    }
    fn error(&mut self, _span: Span, _error: &mut dyn ErrorSink) {
        self.off = true;
    }
}

#[cfg(test)]
#[path = "scene_toml_tests.rs"]
mod tests;
