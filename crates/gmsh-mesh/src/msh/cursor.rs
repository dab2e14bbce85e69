//! A bounds-checked reader over one section of an MSH file, ASCII or binary.
//!
//! Every read names what it expected, so an error says "section $Nodes, line 12, byte offset 345:
//! expected x coordinate of node 7 (double)". Counts are checked against the bytes left in the
//! section before anything is allocated or looped over, so a corrupted count fails at once instead
//! of allocating or spinning.

use crate::error::{Location, MeshError, Result};

/// The whole file being read: its name (for messages) and bytes.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Source<'a> {
    pub name: &'a str,
    pub bytes: &'a [u8],
}

impl<'a> Source<'a> {
    /// Location of `byte_offset` within `section`.
    pub fn location(&self, section: &str, byte_offset: usize) -> Location {
        let clamped = byte_offset.min(self.bytes.len());
        let line = 1 + self.bytes[..clamped]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        Location {
            section: section.to_string(),
            byte_offset,
            line,
        }
    }

    pub fn truncated(
        &self,
        section: &str,
        byte_offset: usize,
        expected: impl Into<String>,
    ) -> MeshError {
        MeshError::Truncated {
            file: self.name.to_string(),
            at: self.location(section, byte_offset),
            expected: expected.into(),
        }
    }

    pub fn syntax(
        &self,
        section: &str,
        byte_offset: usize,
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> MeshError {
        MeshError::Syntax {
            file: self.name.to_string(),
            at: self.location(section, byte_offset),
            expected: expected.into(),
            found: found.into(),
        }
    }
}

/// Description of an expected value, built only when an error is reported (the hot loops over
/// nodes and elements pass closures, so nothing is formatted on success).
pub(crate) trait Expected {
    /// The description, e.g. "x coordinate of node 7".
    fn text(&self) -> String;
}

impl Expected for &str {
    fn text(&self) -> String {
        (*self).to_string()
    }
}

impl Expected for String {
    fn text(&self) -> String {
        self.clone()
    }
}

impl Expected for &String {
    fn text(&self) -> String {
        (*self).clone()
    }
}

impl<F: Fn() -> String> Expected for F {
    fn text(&self) -> String {
        self()
    }
}

/// Encoding of the numbers in a section.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Encoding {
    /// Whitespace-separated decimal text.
    Ascii,
    /// Little-endian binary; `size_t` has the given width in bytes (4 or 8).
    Binary { size_t_bytes: usize },
}

/// Width in bytes of a binary `int` in MSH 4.1.
const INT_BYTES: usize = 4;
/// Width in bytes of a binary `double` in MSH 4.1.
const DOUBLE_BYTES: usize = 8;
/// Longest ASCII token shown in an error message.
const MAX_SHOWN_TOKEN_CHARS: usize = 40;

/// Reader over `source.bytes[pos..end]`, the content of one section.
#[derive(Debug)]
pub(crate) struct Cursor<'a> {
    pub source: Source<'a>,
    pub section: &'static str,
    pub encoding: Encoding,
    pub pos: usize,
    pub end: usize,
}

impl<'a> Cursor<'a> {
    pub fn new(
        source: Source<'a>,
        section: &'static str,
        encoding: Encoding,
        start: usize,
        end: usize,
    ) -> Self {
        Cursor {
            source,
            section,
            encoding,
            pos: start,
            end,
        }
    }

    pub fn truncated(&self, expected: impl Into<String>) -> MeshError {
        self.source.truncated(self.section, self.pos, expected)
    }

    pub fn syntax_at(
        &self,
        offset: usize,
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> MeshError {
        self.source.syntax(self.section, offset, expected, found)
    }

    fn skip_whitespace(&mut self) {
        while self.pos < self.end && self.source.bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    /// Next whitespace-delimited ASCII token and its offset.
    pub fn token(&mut self, expected: impl Expected) -> Result<(usize, &'a str)> {
        self.skip_whitespace();
        if self.pos >= self.end {
            return Err(self.truncated(expected.text()));
        }
        let start = self.pos;
        while self.pos < self.end && !self.source.bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        let raw = &self.source.bytes[start..self.pos];
        match std::str::from_utf8(raw) {
            Ok(text) => Ok((start, text)),
            Err(_) => Err(self.syntax_at(start, expected.text(), describe_bytes(raw))),
        }
    }

    /// Next ASCII token parsed as `T`.
    pub fn ascii<T: std::str::FromStr>(&mut self, expected: impl Expected) -> Result<T> {
        let (offset, text) = self.token(|| expected.text())?;
        text.parse::<T>()
            .map_err(|_| self.syntax_at(offset, expected.text(), format!("\"{}\"", shorten(text))))
    }

    fn take(&mut self, count: usize, expected: impl Expected) -> Result<&'a [u8]> {
        if self.end - self.pos < count {
            return Err(self.truncated(expected.text()));
        }
        let bytes = &self.source.bytes[self.pos..self.pos + count];
        self.pos += count;
        Ok(bytes)
    }

    /// A `size_t` value (node/element tags, counts).
    pub fn size_t(&mut self, expected: impl Expected) -> Result<u64> {
        match self.encoding {
            Encoding::Ascii => {
                self.ascii::<u64>(|| format!("{} (unsigned integer)", expected.text()))
            }
            Encoding::Binary { size_t_bytes } => {
                let bytes = self.take(size_t_bytes, || {
                    format!("{} ({size_t_bytes}-byte size_t)", expected.text())
                })?;
                let mut word = [0u8; 8];
                word[..size_t_bytes].copy_from_slice(bytes);
                Ok(u64::from_le_bytes(word))
            }
        }
    }

    /// An `int` value (entity tags, dimensions, element types, physical tags).
    pub fn int(&mut self, expected: impl Expected) -> Result<i32> {
        match self.encoding {
            Encoding::Ascii => self.ascii::<i32>(|| format!("{} (integer)", expected.text())),
            Encoding::Binary { .. } => {
                let bytes = self.take(INT_BYTES, || format!("{} (4-byte int)", expected.text()))?;
                let mut word = [0u8; INT_BYTES];
                word.copy_from_slice(bytes);
                Ok(i32::from_le_bytes(word))
            }
        }
    }

    /// A `double` value (coordinates, affine transforms).
    pub fn double(&mut self, expected: impl Expected) -> Result<f64> {
        match self.encoding {
            Encoding::Ascii => {
                self.ascii::<f64>(|| format!("{} (floating-point number)", expected.text()))
            }
            Encoding::Binary { .. } => {
                let bytes = self.take(DOUBLE_BYTES, || {
                    format!("{} (8-byte double)", expected.text())
                })?;
                let mut word = [0u8; DOUBLE_BYTES];
                word.copy_from_slice(bytes);
                Ok(f64::from_le_bytes(word))
            }
        }
    }

    /// Smallest number of bytes one `size_t` occupies (ASCII: a digit and a separator).
    pub fn min_size_t_bytes(&self) -> usize {
        match self.encoding {
            Encoding::Ascii => 2,
            Encoding::Binary { size_t_bytes } => size_t_bytes,
        }
    }

    /// Smallest number of bytes one `int` occupies.
    pub fn min_int_bytes(&self) -> usize {
        match self.encoding {
            Encoding::Ascii => 2,
            Encoding::Binary { .. } => INT_BYTES,
        }
    }

    /// Smallest number of bytes one `double` occupies.
    pub fn min_double_bytes(&self) -> usize {
        match self.encoding {
            Encoding::Ascii => 2,
            Encoding::Binary { .. } => DOUBLE_BYTES,
        }
    }

    /// A count of items read as `size_t`, checked to fit in the rest of the section given that
    /// each item takes at least `min_item_bytes`.
    pub fn count(&mut self, expected: impl Expected, min_item_bytes: usize) -> Result<usize> {
        let offset = self.pos;
        let value = self.size_t(|| expected.text())?;
        self.check_count(offset, value, &expected.text(), min_item_bytes)
    }

    /// Check that `value` items of at least `min_item_bytes` each fit in the rest of the section.
    pub fn check_count(
        &self,
        offset: usize,
        value: u64,
        expected: &str,
        min_item_bytes: usize,
    ) -> Result<usize> {
        let remaining = (self.end - self.pos) as u64;
        let needed = value.saturating_mul(min_item_bytes.max(1) as u64);
        if needed > remaining {
            return Err(self.source.truncated(
                self.section,
                offset,
                format!(
                    "{expected}: {value} items need at least {needed} bytes but only {remaining} \
                     remain in the section"
                ),
            ));
        }
        usize::try_from(value)
            .map_err(|_| self.syntax_at(offset, expected, format!("{value} (too large)")))
    }

    /// After the last value: only whitespace may remain before the `$End` tag.
    pub fn finish(&mut self) -> Result<()> {
        self.skip_whitespace();
        if self.pos < self.end {
            let rest = &self.source.bytes[self.pos..self.end.min(self.pos + MAX_SHOWN_TOKEN_CHARS)];
            return Err(self.syntax_at(
                self.pos,
                format!("$End{} after the last value", self.section),
                describe_bytes(rest),
            ));
        }
        Ok(())
    }
}

/// Show bytes in an error message: as text when printable, else as hex.
pub(crate) fn describe_bytes(raw: &[u8]) -> String {
    let shown = &raw[..raw.len().min(MAX_SHOWN_TOKEN_CHARS)];
    if shown.iter().all(|b| b.is_ascii_graphic() || *b == b' ') {
        format!("\"{}\"", String::from_utf8_lossy(shown))
    } else {
        let hex: Vec<String> = shown.iter().map(|b| format!("{b:02x}")).collect();
        format!("bytes [{}]", hex.join(" "))
    }
}

fn shorten(text: &str) -> String {
    text.chars().take(MAX_SHOWN_TOKEN_CHARS).collect()
}
