//! iceoryx2's refusals as the operator's errors: a refused permission says whose files are
//! in the way and how to get past them (a run as another user leaves them).

use crate::error::{IpcError, Refusal};
use crate::files;

/// An iceoryx2 failure of `what`.
pub fn failed(what: &str, e: impl Into<Refusal>) -> IpcError {
    let source = e.into();
    match permission_advice(&source) {
        Some(advice) => IpcError::Permissions { what: what.to_string(), source, advice },
        None => IpcError::Service { what: what.to_string(), source },
    }
}

/// As `failed`, for the shared-memory layer's failure of region `what`.
pub(crate) fn shm_failed(what: &str, e: impl Into<Refusal>) -> IpcError {
    let source = e.into();
    match permission_advice(&source) {
        Some(advice) => IpcError::Permissions { what: what.to_string(), source, advice },
        None => IpcError::Shm { what: what.to_string(), source },
    }
}

fn permission_advice(source: &Refusal) -> Option<String> {
    source.is_permission().then(|| files::permission_advice(&files::foreign_files()))
}
