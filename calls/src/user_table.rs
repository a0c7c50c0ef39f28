//! HMPL 11.6/11.7: the user table on the controller's disk. `SaveUserTable` replaces the
//! file whole (write a temporary file, fsync, rename), under a lock that serialises the
//! tasks saving at once, so that a process killed in the middle of a save leaves the old
//! table or the new one, never a mix.

use std::fs::{File, OpenOptions};
use std::io::{Read, Write};
use std::ops::Range;
use std::os::fd::AsRawFd;
use std::path::{Path, PathBuf};

use api::SystemError;
use schema::shared::{SharedData, USER_TABLE_LEN};

const FILE: &str = "user_table.bin";
const BYTES: usize = USER_TABLE_LEN * 8;

/// Why `load` found no table.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// No save was made in that folder.
    #[error("no user table has been saved in {0}")]
    NothingSaved(PathBuf),
    /// The file could not be read.
    #[error(transparent)]
    Io(#[from] std::io::Error),
}

/// An exclusive lock on `<dir>/user_table.lock`, released when dropped (or when the
/// process dies).
struct DirLock(File);

impl DirLock {
    fn take(dir: &Path) -> std::io::Result<Self> {
        let file = OpenOptions::new().create(true).truncate(false).write(true).open(dir.join("user_table.lock"))?;
        // SAFETY: flock on a descriptor this function owns; blocks until the lock is free.
        if unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX) } != 0 {
            return Err(std::io::Error::last_os_error());
        }
        Ok(DirLock(file))
    }
}

impl Drop for DirLock {
    fn drop(&mut self) {
        // SAFETY: unlocking the descriptor locked in `take`.
        unsafe { libc::flock(self.0.as_raw_fd(), libc::LOCK_UN) };
    }
}

/// The saved table, or `None` when there is none (or it is not a whole table).
fn read_saved(path: &Path) -> std::io::Result<Option<Vec<u8>>> {
    let mut bytes = Vec::with_capacity(BYTES);
    match File::open(path) {
        Ok(mut file) => file.read_to_end(&mut bytes)?,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(e),
    };
    Ok((bytes.len() == BYTES).then_some(bytes))
}

/// HMPL 11.6 `SaveUserTable` (`save` true) or 11.7 `LoadUserTable` of `range`: the
/// system error the call answers when it fails (0x... `HimcSaveConfigFail` or
/// `HimcLoadConfigFail`, as in HMPL 18.2), and why.
pub fn save_or_load(
    save: bool,
    dir: &Path,
    shared: &SharedData,
    range: Range<usize>,
) -> Result<(), (SystemError, String)> {
    if save {
        self::save(dir, shared, range).map_err(|e| (SystemError::HimcSaveConfigFail, e.to_string()))
    } else {
        load(dir, shared, range).map_err(|e| (SystemError::HimcLoadConfigFail, e.to_string()))
    }
}

/// Writes `range` of the shared table into the saved one.
pub fn save(dir: &Path, shared: &SharedData, range: Range<usize>) -> std::io::Result<()> {
    let _lock = DirLock::take(dir)?;
    let path = dir.join(FILE);
    let mut bytes = read_saved(&path)?.unwrap_or_else(|| vec![0; BYTES]);
    for i in range {
        let value = shared.user_table(i).unwrap_or(0.0);
        bytes[i * 8..i * 8 + 8].copy_from_slice(&value.to_le_bytes());
    }
    let temporary = dir.join(format!("{FILE}.tmp"));
    let mut file = File::create(&temporary)?;
    file.write_all(&bytes)?;
    file.sync_all()?;
    std::fs::rename(&temporary, &path)?;
    // The rename itself must reach the disk.
    File::open(dir)?.sync_all()
}

/// Copies `range` of the saved table into the shared one.
pub fn load(dir: &Path, shared: &SharedData, range: Range<usize>) -> Result<(), LoadError> {
    let _lock = DirLock::take(dir)?;
    let bytes = read_saved(&dir.join(FILE))?.ok_or_else(|| LoadError::NothingSaved(dir.to_path_buf()))?;
    for i in range {
        let value = f64::from_le_bytes(bytes[i * 8..i * 8 + 8].try_into().expect("8 bytes"));
        shared.set_user_table(i, value);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> Box<SharedData> {
        schema::layout::zeroed()
    }

    /// HMPL 11.1: write [3..5] = 2, 6, 4; save; overwrite; load: 2, 6, 4 again.
    #[test]
    fn the_manuals_save_and_load_example() {
        let dir = tempfile::tempdir().unwrap();
        let shared = table();
        assert!(matches!(load(dir.path(), &shared, 0..1), Err(LoadError::NothingSaved(_))));
        for (i, v) in [(3, 2.0), (4, 6.0), (5, 4.0)] {
            shared.set_user_table(i, v);
        }
        save(dir.path(), &shared, 3..6).unwrap();
        for (i, v) in [(3, 999.0), (4, 777.0), (5, 888.0)] {
            shared.set_user_table(i, v);
        }
        load(dir.path(), &shared, 3..6).unwrap();
        assert_eq!([3, 4, 5].map(|i| shared.user_table(i).unwrap()), [2.0, 6.0, 4.0]);
    }

    /// A save writes its range only; what was saved before elsewhere stays.
    #[test]
    fn a_save_keeps_the_other_ranges() {
        let dir = tempfile::tempdir().unwrap();
        let shared = table();
        shared.set_user_table(0, 1.0);
        save(dir.path(), &shared, 0..1).unwrap();
        shared.set_user_table(0, 5.0);
        shared.set_user_table(511_999, 2.0);
        save(dir.path(), &shared, 511_999..512_000).unwrap();
        let fresh = table();
        load(dir.path(), &fresh, 0..USER_TABLE_LEN).unwrap();
        assert_eq!((fresh.user_table(0), fresh.user_table(511_999)), (Some(1.0), Some(2.0)));
        assert_eq!(std::fs::metadata(dir.path().join(FILE)).unwrap().len(), BYTES as u64);
    }
}
