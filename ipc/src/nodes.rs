//! The namespace's nodes: whether a controller lives in it, and what dead processes left.

use iceoryx2::node::{NodeState, NodeView};
use iceoryx2::prelude::*;

use crate::advice::failed;
use crate::core_side::CORE_NODE_NAME;
use crate::error::IpcError;
use crate::namespace::Namespace;
use crate::services;

/// Makes the namespace ready for a new controller: removes what dead processes left
/// behind (so that a `kill -9` never blocks the next start) and refuses if a controller
/// is alive in it.
pub fn claim_namespace(ns: &Namespace) -> Result<(), IpcError> {
    match scan_nodes(ns, true)? {
        Some(pid) => Err(IpcError::NamespaceInUse { ns: ns.to_string(), pid }),
        None => Ok(()),
    }
}

/// The pid of the controller alive in the namespace, if any.
pub fn controller_pid(ns: &Namespace) -> Result<Option<u32>, IpcError> {
    scan_nodes(ns, false)
}

/// Whether a live controller in `ns` serves everything a program attaches to: its event
/// stream, which its supervisor creates last, is up.
pub fn controller_ready(ns: &Namespace) -> Result<bool, IpcError> {
    if controller_pid(ns)?.is_none() {
        return Ok(false);
    }
    let node = services::node(ns, &format!("luamotion-probe-{}", std::process::id()))?;
    Ok(services::events(&node, ns, services::Open::Existing).is_ok())
}

/// Lists the namespace's nodes: the live controller's pid, removing dead nodes if asked.
fn scan_nodes(ns: &Namespace, remove_dead: bool) -> Result<Option<u32>, IpcError> {
    let mut alive_core = None;
    Node::<services::Ipc>::list(&ns.config(), |state| {
        match state {
            NodeState::Alive(view) => {
                if let Some(details) = view.details()
                    && details.name().as_str() == CORE_NODE_NAME
                {
                    alive_core = Some(details.process_id().value() as u32);
                }
            }
            NodeState::Dead(view) if remove_dead => {
                // Another process may be cleaning the same node; either way it is gone after.
                let _ = view.try_remove_stale_resources();
            }
            NodeState::Dead(_) | NodeState::Inaccessible(_) | NodeState::Undefined(_) => {}
        }
        CallbackProgression::Continue
    })
    .map_err(|e| failed("list nodes", e))?;
    Ok(alive_core)
}

/// Removes the stale resources of dead processes (e.g. a killed script) in the namespace.
pub fn clean_dead_nodes(ns: &Namespace) {
    let _ = Node::<services::Ipc>::list(&ns.config(), |state| {
        if let NodeState::Dead(view) = state {
            let _ = view.try_remove_stale_resources();
        }
        CallbackProgression::Continue
    });
}
