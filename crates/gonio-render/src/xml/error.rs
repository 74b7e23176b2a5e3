//! Scene loading errors. Every error names the file, the line and column of the offending element
//! or attribute value, and the value itself, so a user can fix the scene without guessing.

use std::fmt;
use std::sync::Arc;

/// A place in a scene file (1-based line and column; 0 when only the file is known).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    /// The file, as given or resolved (`<string>` for in-memory text).
    pub file: Arc<str>,
    /// Line, 1-based (0 = unknown).
    pub line: u32,
    /// Column, 1-based (0 = unknown).
    pub column: u32,
}

impl Location {
    /// A location covering a whole file.
    pub fn file_only(file: Arc<str>) -> Self {
        Self {
            file,
            line: 0,
            column: 0,
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            write!(f, "{}", self.file)
        } else {
            write!(f, "{}:{}:{}", self.file, self.line, self.column)
        }
    }
}

/// What went wrong, for callers (and tests) that branch on the kind of error.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// The file is not well-formed XML.
    Syntax,
    /// An element, attribute or structure that the grammar does not allow.
    Grammar,
    /// A plugin name we do not know (or do not support).
    UnknownPlugin,
    /// A parameter the plugin did not use (misspelt or unsupported).
    UnusedParameter,
    /// A parameter of the wrong type (a string where a float is expected, ...).
    WrongType,
    /// A value that cannot be parsed or is out of range (bad number, NaN IOR, negative radius...).
    BadValue,
    /// `$name` without a `<default>` or `-D` definition, or an unused `-D`.
    Undefined,
    /// A `<ref>` to an id that does not exist, or an id defined twice.
    Reference,
    /// A reference or include cycle.
    Cycle,
    /// A file that cannot be read (include, mesh, image, spectrum).
    Io,
    /// A mesh file that cannot be parsed.
    Mesh,
    /// An image file that cannot be decoded.
    Image,
    /// A preset name (IOR, conductor, glass) we do not know.
    UnknownPreset,
}

/// An error while loading a scene: where, what kind, and a message that quotes the offending value.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{location}: {message}")]
pub struct SceneError {
    /// Where.
    pub location: Location,
    /// What kind of problem.
    pub kind: ErrorKind,
    /// The message, quoting the offending value.
    pub message: String,
}

impl SceneError {
    /// A new error.
    pub fn new(location: Location, kind: ErrorKind, message: impl Into<String>) -> Self {
        Self {
            location,
            kind,
            message: message.into(),
        }
    }
}
