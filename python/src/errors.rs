//! Library errors → Python exceptions carrying the command line's one-line message.
//!
//! The message is built exactly as `sawdrive`'s `main.rs` prints it after `error: `: the error
//! and its causes joined by ": ", a cause already contained in the line not repeated, newlines
//! replaced by spaces and control bytes escaped. The exception classes live in
//! `sawdrive/errors.py` (so that they can derive from both `SawdriveError` and `ValueError`).

use pyo3::prelude::*;

/// Which Python exception a failure becomes (classes of `sawdrive.errors`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Bad scene content: unknown key, wrong unit or type, out of range (`ValueError`).
    Scene,
    /// A file that cannot be read (`OSError`).
    File,
    /// A stage failed on a valid scene (`RuntimeError`).
    Pipeline,
    /// A sweep file is malformed (`ValueError`).
    Sweep,
    /// Bad arguments of a call, e.g. `--jobs 0` (`ValueError`).
    Argument,
}

impl Kind {
    fn class_name(self) -> &'static str {
        match self {
            Kind::Scene => "SceneError",
            Kind::File => "SceneFileError",
            Kind::Pipeline => "PipelineError",
            Kind::Sweep => "SweepError",
            Kind::Argument => "ArgumentError",
        }
    }
}

/// A failure on its way to Python: the exception class and the CLI's one-line message.
#[derive(Debug, Clone)]
pub struct Failure {
    /// Exception class.
    pub kind: Kind,
    /// One line, as the CLI prints it after `error: `.
    pub message: String,
}

impl Failure {
    /// A failure of class `kind` with the one-line message of `error`.
    pub fn new(kind: Kind, error: &(dyn std::error::Error + 'static)) -> Self {
        Self {
            kind,
            message: one_line(error),
        }
    }

    /// A failure with a message written here (no library error behind it).
    pub fn text(kind: Kind, message: impl Into<String>) -> Self {
        Self {
            kind,
            message: message.into(),
        }
    }

    /// The Python exception (an instance of the `sawdrive.errors` class).
    pub fn into_pyerr(self, py: Python<'_>) -> PyErr {
        let class = py
            .import("sawdrive.errors")
            .and_then(|m| m.getattr(self.kind.class_name()));
        match class.and_then(|c| c.call1((self.message.clone(),))) {
            Ok(instance) => PyErr::from_value(instance),
            Err(e) => e,
        }
    }
}

/// The error and its causes on one line (the CLI's `error_chain`).
pub fn one_line(error: &(dyn std::error::Error + 'static)) -> String {
    let mut line = String::new();
    let mut cause: Option<&(dyn std::error::Error + 'static)> = Some(error);
    while let Some(e) = cause {
        let text = e.to_string();
        if !line.contains(&text) {
            if !line.is_empty() {
                line.push_str(": ");
            }
            line.push_str(&text);
        }
        cause = e.source();
    }
    gmsh_mesh::escape_control(&line.replace('\n', " "))
}

impl From<sawdrive::scene::SceneError> for Failure {
    fn from(error: sawdrive::scene::SceneError) -> Self {
        let kind = match error {
            sawdrive::scene::SceneError::Io { .. } => Kind::File,
            _ => Kind::Scene,
        };
        Failure::new(kind, &error)
    }
}

impl From<sawdrive::pipeline::PipelineError> for Failure {
    fn from(error: sawdrive::pipeline::PipelineError) -> Self {
        Failure::new(Kind::Pipeline, &error)
    }
}

impl From<contact_springs::SpringError> for Failure {
    fn from(error: contact_springs::SpringError) -> Self {
        sawdrive::pipeline::PipelineError::from(error).into()
    }
}

impl From<sawdrive::output::OutputError> for Failure {
    fn from(error: sawdrive::output::OutputError) -> Self {
        Failure::new(Kind::Pipeline, &error)
    }
}

impl From<serde_json::Error> for Failure {
    fn from(error: serde_json::Error) -> Self {
        Failure::new(Kind::Pipeline, &error)
    }
}

impl From<sawdrive::sweep::SweepError> for Failure {
    fn from(error: sawdrive::sweep::SweepError) -> Self {
        let kind = match error {
            sawdrive::sweep::SweepError::Io { .. } => Kind::File,
            _ => Kind::Sweep,
        };
        Failure::new(kind, &error)
    }
}

impl From<sawdrive::sweep::SweepRunError> for Failure {
    fn from(error: sawdrive::sweep::SweepRunError) -> Self {
        use sawdrive::sweep::SweepRunError as E;
        let kind = match &error {
            E::File(_) | E::UnknownColumn { .. } => Kind::Sweep,
            E::Scene { .. } => Kind::Scene,
            E::Jobs { .. } => Kind::Argument,
            _ => Kind::Pipeline,
        };
        Failure::new(kind, &error)
    }
}

impl From<::design::StudyError> for Failure {
    /// Bad study input (`[scatter]`, a design file) is a scene error, an unreadable file a file
    /// error, a failed model run a pipeline error — as the errors inside say.
    fn from(error: ::design::StudyError) -> Self {
        use ::design::StudyError as E;
        let kind = match &error {
            E::Input { .. } | E::Conflict(_) => Kind::Scene,
            E::File { source, .. } => return Failure::new(Failure::from_ref(source).kind, &error),
            E::Io(_) => Kind::File,
            E::Model(inner) => model_kind(inner.as_ref()),
            _ => Kind::Pipeline,
        };
        Failure::new(kind, &error)
    }
}

impl Failure {
    /// The kind a study error would get (for an error inside a design file's).
    fn from_ref(error: &::design::StudyError) -> Self {
        use ::design::StudyError as E;
        let kind = match error {
            E::Input { .. } | E::Conflict(_) | E::File { .. } => Kind::Scene,
            E::Io(_) => Kind::File,
            E::Model(inner) => model_kind(inner.as_ref()),
            _ => Kind::Pipeline,
        };
        Failure::new(kind, error)
    }
}

/// The kind of the evaluator's error: the scene's (file or content) or the pipeline's.
fn model_kind(error: &(dyn std::error::Error + Send + Sync + 'static)) -> Kind {
    match error.downcast_ref::<sawdrive::scene::SceneError>() {
        Some(sawdrive::scene::SceneError::Io { .. }) => Kind::File,
        Some(_) => Kind::Scene,
        None => Kind::Pipeline,
    }
}
