//! Where a namespace's files live (iceoryx2's folders and `/dev/shm`), their removal, and
//! what to tell a user whose run is refused another user's files.

use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

use crate::namespace::Namespace;
use crate::namespace::base_config;

/// Where POSIX shared memory is (every `lm.<ns>.` region and iceoryx2 data segment).
const SHM_DIR: &str = "/dev/shm";
/// Prefix of every file luamotion's namespaces create (`Namespace::prefix`).
const PREFIX: &str = "lm.";

/// iceoryx2's root folder and the node and service folders under it.
fn iceoryx2_dirs() -> [PathBuf; 3] {
    let global = base_config().global;
    // Without the trailing slash iceoryx2 keeps, so that paths read as users type them.
    let path = |p: iceoryx2_bb_system_types::path::Path| PathBuf::from(p.to_string()).components().collect();
    [path(*global.root_path()), path(global.node_dir()), path(global.service_dir())]
}

/// Removes every file the namespace left in shared memory and in iceoryx2's folders.
/// Call it once the controller and its scripts are gone.
pub fn remove_namespace_files(ns: &Namespace) {
    let prefix = ns.prefix();
    let [_, nodes, services] = iceoryx2_dirs();
    for dir in [PathBuf::from(SHM_DIR), nodes, services] {
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        for entry in entries.flatten() {
            if entry.file_name().to_string_lossy().starts_with(&prefix) {
                let path = entry.path();
                let _ = if path.is_dir() { std::fs::remove_dir_all(&path) } else { std::fs::remove_file(&path) };
            }
        }
    }
}

/// Free space in `/dev/shm`, bytes.
pub fn shm_free_bytes() -> Option<usize> {
    let path = std::ffi::CString::new(SHM_DIR).expect("no NUL");
    // SAFETY: statvfs is plain data, valid when zeroed.
    let mut stat: libc::statvfs = unsafe { std::mem::zeroed() };
    // SAFETY: a valid path and a statvfs to fill.
    if unsafe { libc::statvfs(path.as_ptr(), &mut stat) } != 0 {
        return None;
    }
    Some(stat.f_bavail as usize * stat.f_frsize as usize)
}

/// What is in the way of this process: one of iceoryx2's folders, or one namespace's
/// files in a folder.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Foreign {
    /// An iceoryx2 folder another user owns.
    Folder {
        /// The folder.
        path: PathBuf,
        /// Its owner.
        uid: u32,
    },
    /// A namespace's files another user owns.
    Files {
        /// The folder they are in.
        dir: PathBuf,
        /// The namespace.
        ns: String,
        /// How many.
        count: usize,
        /// Their owner.
        uid: u32,
    },
}

impl std::fmt::Display for Foreign {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Foreign::Folder { path, uid } => write!(f, "{} (uid {uid})", path.display()),
            Foreign::Files { dir, ns, count, uid } => {
                write!(f, "{}/{PREFIX}{ns}.* ({count} files of uid {uid})", dir.display())
            }
        }
    }
}

/// What another user left that this process may not use: iceoryx2's folders it may not
/// write into, and luamotion's files in them and in `/dev/shm` it may not read and write
/// (typically after a run as root).
pub fn foreign_files() -> Vec<Foreign> {
    let [root, nodes, services] = iceoryx2_dirs();
    let mut found: Vec<Foreign> = [&root, &nodes, &services]
        .into_iter()
        .filter(|dir| dir.exists() && !accessible(dir, libc::W_OK | libc::X_OK))
        .filter_map(|dir| Some(Foreign::Folder { path: dir.clone(), uid: std::fs::metadata(dir).ok()?.uid() }))
        .collect();
    for dir in [PathBuf::from(SHM_DIR), nodes, services] {
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        for entry in entries.flatten() {
            let path = entry.path();
            let Some(ns) = namespace_of(&path) else { continue };
            if accessible(&path, libc::R_OK | libc::W_OK) {
                continue;
            }
            let Ok(uid) = entry.metadata().map(|m| m.uid()) else { continue };
            let same = |f: &&mut Foreign| matches!(f, Foreign::Files { dir: d, ns: n, uid: u, .. } if *d == dir && *n == ns && *u == uid);
            match found.iter_mut().find(|f| same(f)) {
                Some(Foreign::Files { count, .. }) => *count += 1,
                _ => found.push(Foreign::Files { dir: dir.clone(), ns, count: 1, uid }),
            }
        }
    }
    found
}

fn accessible(path: &Path, mode: libc::c_int) -> bool {
    let Ok(c_path) = std::ffi::CString::new(path.as_os_str().as_encoded_bytes()) else { return false };
    // SAFETY: a valid NUL-terminated path; `access` only reads it.
    unsafe { libc::access(c_path.as_ptr(), mode) == 0 }
}

/// What to tell the user about `found`: what is in the way, whose, and how to get past it.
pub fn permission_advice(found: &[Foreign]) -> String {
    // SAFETY: getuid cannot fail.
    let me = unsafe { libc::getuid() };
    let [root, ..] = iceoryx2_dirs();
    if found.is_empty() {
        return format!(
            "this user (uid {me}) may not use iceoryx2's files in {} or {SHM_DIR}/{PREFIX}*; remove them as their \
             owner once no luamotion runs, or run as the user that created them",
            root.display()
        );
    }
    let listed: Vec<String> = found.iter().map(Foreign::to_string).collect();
    // A folder in the way blocks every namespace; files of one namespace only that one.
    let folder_blocked = found.iter().any(|f| matches!(f, Foreign::Folder { .. }));
    let remove = if folder_blocked {
        format!("sudo rm -rf {} {SHM_DIR}/{PREFIX}*", root.display())
    } else {
        let mut namespaces: Vec<&str> = found
            .iter()
            .filter_map(|f| if let Foreign::Files { ns, .. } = f { Some(ns.as_str()) } else { None })
            .collect();
        namespaces.sort_unstable();
        namespaces.dedup();
        let patterns: Vec<String> = namespaces
            .iter()
            .map(|ns| format!("{SHM_DIR}/{PREFIX}{ns}.* {}/*/{PREFIX}{ns}.*", root.display()))
            .collect();
        format!("sudo rm -rf {}", patterns.join(" "))
    };
    let other_ns = if folder_blocked { "" } else { ", or use another --ns" };
    format!(
        "another user's run left what this user (uid {me}) may not use: {}. Remove it once no luamotion runs \
         (`{remove}`), or run as the user that owns it{other_ns}",
        listed.join(", ")
    )
}

/// The namespace a file of luamotion's belongs to: `lm.<ns>.<rest>`.
fn namespace_of(path: &Path) -> Option<String> {
    let name = path.file_name()?.to_str()?.strip_prefix(PREFIX)?;
    Some(name.split_once('.')?.0.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn advice_names_the_files_their_owner_and_the_fix() {
        let found = [Foreign::Files { dir: SHM_DIR.into(), ns: "cell1".into(), count: 12, uid: 0 }];
        let advice = permission_advice(&found);
        assert!(advice.contains("/dev/shm/lm.cell1.* (12 files of uid 0)"), "{advice}");
        assert!(advice.contains("sudo rm -rf /dev/shm/lm.cell1.* /dev/shm/iceoryx2/*/lm.cell1.*"), "{advice}");
        assert!(advice.contains("another --ns"), "a namespace's own files block only it: {advice}");
    }

    #[test]
    fn a_folder_in_the_way_blocks_every_namespace() {
        let [root, nodes, _] = iceoryx2_dirs();
        let advice = permission_advice(&[Foreign::Folder { path: nodes.clone(), uid: 0 }]);
        assert!(advice.contains(&format!("{} (uid 0)", nodes.display())), "{advice}");
        assert!(advice.contains(&format!("sudo rm -rf {} /dev/shm/lm.*", root.display())), "{advice}");
        assert!(!advice.contains("--ns"), "another namespace would not help: {advice}");
    }

    #[test]
    fn namespaces_of_files() {
        assert_eq!(namespace_of(Path::new("/dev/shm/lm.t1-2-x.tasks")).as_deref(), Some("t1-2-x"));
        assert_eq!(namespace_of(Path::new("/tmp/iceoryx2/nodes/other")), None);
    }
}
