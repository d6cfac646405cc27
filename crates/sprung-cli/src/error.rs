//! The command line's one error type: why a command failed, and the exit
//! status that says so (1 for bad input or a failed write, 3 for a
//! blow-up, 128 + the signal for SIGINT or SIGTERM, a child's own status).

use std::fmt;

use sprung::StepError;
use sprung_io::SceneError;

use crate::interrupt::Signal;

/// Why a command failed.
#[derive(Debug)]
pub enum CliError {
    /// A scene or an option that cannot be used (nothing was run).
    Input(String),
    /// The scene file's own error.
    Scene(SceneError),
    /// A file that could not be written.
    Io(String),
    /// A program we started (the viewer) failed with this exit status;
    /// `sprung` exits with the same status.
    Child(i32, String),
    /// The simulation blew up; what was recorded up to it was kept: the
    /// second field is the sentence that says what and where.
    BlowUp(StepError, String),
    /// SIGINT or SIGTERM stopped the run at the end of a step; what was
    /// recorded was kept: the sentence says where.
    Interrupted(Signal, String),
}

impl CliError {
    /// The process exit status for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::BlowUp(..) => 3,
            CliError::Interrupted(signal, _) => signal.exit_code(),
            CliError::Child(code, _) => u8::try_from(*code).unwrap_or(1),
            _ => 1,
        }
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CliError::Input(m) | CliError::Io(m) | CliError::Child(_, m) => f.write_str(m),
            CliError::Scene(e) => write!(f, "{e}"),
            CliError::BlowUp(e, kept) => write!(f, "{e}\n({kept})"),
            CliError::Interrupted(signal, m) => write!(f, "{}: {m}", signal.name()),
        }
    }
}

impl From<SceneError> for CliError {
    fn from(e: SceneError) -> Self {
        CliError::Scene(e)
    }
}
