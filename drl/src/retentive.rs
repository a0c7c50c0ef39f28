//! DH, the retentive Modbus area (DXMC A.1): kept in `<data dir>/dh.bin` and written
//! atomically (a temporary file, fsync, rename), so that a crash leaves the old contents
//! or the new ones, never a mix.

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

pub fn save(dir: &Path, bytes: &[u8]) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let temporary = dir.join(format!(".{FILE}.{}", std::process::id()));
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
}
