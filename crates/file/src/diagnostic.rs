//! Errors in a scene file, pointing into it as rustc points into source: the file, the line
//! and column, the line itself with the part underlined, and a hint.

use codespan_reporting::diagnostic::{Diagnostic as Report, Label};
use codespan_reporting::files::SimpleFile;
use codespan_reporting::term;
use std::fmt;
use std::ops::Range;

/// One error in a scene file: where ([`line_column`](Self::line_column)), what
/// ([`message`](Self::message)), what would be right ([`hint`](Self::hint)), drawn on the file's
/// text by [`render`](Self::render).
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic(Box<Parts>);

#[derive(Clone, Debug, PartialEq)]
struct Parts {
    path: String,
    source: String,
    message: String,
    span: Range<usize>,
    label: String,
    hint: Option<String>,
}

impl Diagnostic {
    /// An error about `span` of the file `path` whose text is `source`.
    pub fn new(path: &str, source: &str, span: Range<usize>, message: impl Into<String>) -> Self {
        let end = span.end.min(source.len());
        let start = span.start.min(end);
        Self(Box::new(Parts {
            path: path.to_string(),
            source: source.to_string(),
            message: message.into(),
            span: start..end,
            label: String::new(),
            hint: None,
        }))
    }

    /// What is wrong.
    pub fn message(&self) -> &str {
        &self.0.message
    }

    /// What would be right, where a hint helps.
    pub fn hint(&self) -> Option<&str> {
        self.0.hint.as_deref()
    }

    /// The bytes of the file the error is about.
    pub fn span(&self) -> Range<usize> {
        self.0.span.clone()
    }

    /// The same with a label under the underlined part.
    pub fn label(mut self, label: impl Into<String>) -> Self {
        self.0.label = label.into();
        self
    }

    /// The same with a hint.
    pub fn with_hint(mut self, hint: Option<String>) -> Self {
        self.0.hint = hint;
        self
    }

    /// Line and column (both from 1; the column counts characters) where the error points.
    pub fn line_column(&self) -> (usize, usize) {
        let before = &self.0.source[..floor_char_boundary(&self.0.source, self.0.span.start)];
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        (line, column)
    }

    /// The error as rustc prints one (no colour).
    pub fn render(&self) -> String {
        let file = SimpleFile::new(self.0.path.as_str(), self.0.source.as_str());
        let span = floor_char_boundary(&self.0.source, self.0.span.start)
            ..floor_char_boundary(&self.0.source, self.0.span.end);
        let mut report = Report::error()
            .with_message(&self.0.message)
            .with_labels(vec![Label::primary((), span).with_message(&self.0.label)]);
        if let Some(hint) = &self.0.hint {
            report = report.with_notes(vec![format!("help: {hint}")]);
        }
        let mut out = term::termcolor::NoColor::new(Vec::new());
        if term::emit(&mut out, &term::Config::default(), &file, &report).is_err() {
            let (line, column) = self.line_column();
            return format!("error: {}\n  --> {}:{line}:{column}\n", self.0.message, self.0.path);
        }
        String::from_utf8_lossy(&out.into_inner()).into_owned()
    }
}

fn floor_char_boundary(text: &str, mut index: usize) -> usize {
    index = index.min(text.len());
    while !text.is_char_boundary(index) {
        index -= 1;
    }
    index
}

impl fmt::Display for Diagnostic {
    /// `path:line:column: message` (one line; [`render`](Self::render) draws the source).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (line, column) = self.line_column();
        write!(f, "{}:{line}:{column}: {}", self.0.path, self.0.message)
    }
}

impl std::error::Error for Diagnostic {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_at_line_and_column_and_draws_the_line() {
        let source = "version = 1\nid = \"x\"\nmass = \"m*θ + q\"\n";
        let at = source.find("q\"").unwrap();
        let d = Diagnostic::new("pendulum.toml", source, at..at + 1, "unknown name `q`")
            .label("not a parameter, coordinate or rate")
            .with_hint(Some("did you mean `θ`?".into()));
        assert_eq!(d.line_column(), (3, 15));
        assert_eq!(d.to_string(), "pendulum.toml:3:15: unknown name `q`");
        let text = d.render();
        assert!(text.contains("error: unknown name `q`"), "{text}");
        assert!(text.contains("pendulum.toml:3:15"), "{text}");
        assert!(text.contains("mass = \"m*θ + q\""), "{text}");
        assert!(text.contains("help: did you mean `θ`?"), "{text}");
    }
}
