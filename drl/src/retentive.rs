//! DH, the retentive Modbus area (DXMC A.1): kept in `<data dir>/dh.bin` and written
//! atomically (a temporary file, fsync, rename), so that a crash leaves the old contents
//! or the new ones, never a mix. A crash can leave its temporary file behind: the next
//! start removes those (`remove_leftovers`).

use std::io::Write;
use std::path::{Path, PathBuf};

const FILE: &str = "dh.bin";

fn path(dir: &Path) -> PathBuf {
    dir.join(FILE)
}

/// The saved DH, if any.
pub fn load(dir: &Path) -> std::io::Result<Option<Vec<u8>>> {
    match std::fs::read(path(dir)) {
        Ok(bytes) => Ok(Some(bytes)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e),
    }
}

/// The temporary files of saves, `.dh.bin.<pid>`.
fn temporary_prefix() -> String {
    format!(".{FILE}.")
}

/// Removes the temporary files saves left behind when their process was killed; run at
/// start, before the first save (a data dir serves one controller at a time). Returns
/// how many there were.
pub fn remove_leftovers(dir: &Path) -> std::io::Result<usize> {
    let entries = match std::fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(0),
        Err(e) => return Err(e),
    };
    let mut removed = 0;
    for entry in entries {
        let entry = entry?;
        if entry.file_name().to_string_lossy().starts_with(&temporary_prefix()) && entry.file_type()?.is_file() {
            std::fs::remove_file(entry.path())?;
            removed += 1;
        }
    }
    Ok(removed)
}

pub fn save(dir: &Path, bytes: &[u8]) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let temporary = dir.join(format!("{}{}", temporary_prefix(), std::process::id()));
    let mut file = std::fs::File::create(&temporary)?;
    file.write_all(bytes)?;
    file.sync_all()?;
    std::fs::rename(&temporary, path(dir))?;
    // The rename itself is durable once the folder is synced.
    std::fs::File::open(dir)?.sync_all()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn saved_dh_comes_back_and_replaces_the_old() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(load(dir.path()).unwrap(), None);
        save(dir.path(), &[1, 2, 3, 4]).unwrap();
        save(dir.path(), &[5, 6]).unwrap();
        assert_eq!(load(dir.path()).unwrap(), Some(vec![5, 6]));
        let leftovers = std::fs::read_dir(dir.path()).unwrap().count();
        assert_eq!(leftovers, 1, "no temporary file left behind");
    }

    #[test]
    fn leftovers_of_killed_saves_go_and_nothing_else() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(remove_leftovers(&dir.path().join("none")).unwrap(), 0, "no data dir yet");
        save(dir.path(), &[1, 2]).unwrap();
        for name in [".dh.bin.123", ".dh.bin.4294967295", "dh.bin.bak", "notes.dh.bin.1"] {
            std::fs::write(dir.path().join(name), b"x").unwrap();
        }
        assert_eq!(remove_leftovers(dir.path()).unwrap(), 2);
        let mut names: Vec<String> =
            std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into()).collect();
        names.sort();
        assert_eq!(names, ["dh.bin", "dh.bin.bak", "notes.dh.bin.1"]);
        assert_eq!(load(dir.path()).unwrap(), Some(vec![1, 2]));
    }
}
