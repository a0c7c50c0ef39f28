//! DRL projects on disk (DXMC manual 8.3, A.3): project `id` (0..9999) is the folder
//! `<projects>/<id>` holding `main.lua` and the modules it requires. The projects folder
//! is the controller's FTP area; the export folder stands for the USB stick.

use std::path::{Path, PathBuf};

/// DXMC A.3, register 0x6B04: DRL ids 0..9999.
pub const MAX_ID: u16 = 9999;
/// The entry script of a project.
pub const MAIN: &str = "main.lua";

/// Why a project cannot be opened, exported or imported.
#[derive(Debug, thiserror::Error)]
pub enum ProjectError {
    /// The project's folder has no `main.lua` (the id and the path looked at).
    #[error("project {0}: no {MAIN} in {1}")]
    Missing(u16, PathBuf),
    /// `main.lua` does not compile.
    #[error("project {id}: {message}")]
    Syntax {
        /// The project's DRL id.
        id: u16,
        /// Lua's message, `file:line: ...`.
        message: String,
    },
    /// `luamotion check` found errors in `main.lua`: it would fail or do what it cannot
    /// mean once running (an unknown API name, a wrong argument).
    #[error("project {id}: the check found errors:\n{findings}")]
    Check {
        /// The project's DRL id.
        id: u16,
        /// The check's findings, as `luamotion check` prints them.
        findings: String,
    },
    /// The path of `main.lua` does not fit the task table's program field.
    #[error("project {id}: the path of {MAIN} is too long for the task table ({path})")]
    PathTooLong {
        /// The project's DRL id.
        id: u16,
        /// The path that does not fit.
        path: PathBuf,
    },
    /// A file operation on this path failed.
    #[error("{0}: {1}")]
    Io(PathBuf, std::io::Error),
}

/// Where the DRL projects are: one folder per DRL id holding `main.lua`.
#[derive(Clone, Debug)]
pub struct Projects {
    /// The projects (the DXMC's FTP area), `<dir>/<id>/main.lua`.
    pub dir: PathBuf,
    /// Where Export copies a project and Import takes it from (the DXMC's USB stick).
    pub export: PathBuf,
}

impl Projects {
    /// The `main.lua` of project `id`.
    pub fn main_lua(&self, id: u16) -> PathBuf {
        self.dir.join(id.to_string()).join(MAIN)
    }

    /// "Open" (DXMC A.3, status 1 CHECKING): the project exists, its `main.lua` compiles
    /// and `luamotion check` finds no error in it. Returns the path the script process runs.
    pub fn check(&self, id: u16) -> Result<PathBuf, ProjectError> {
        let path = self.main_lua(id);
        let source = std::fs::read_to_string(&path).map_err(|_| ProjectError::Missing(id, path.clone()))?;
        let path = path.canonicalize().map_err(|e| ProjectError::Io(path.clone(), e))?;
        if path.as_os_str().len() >= ipc::task_table::PROGRAM_BYTES {
            return Err(ProjectError::PathTooLong { id, path });
        }
        let lua = mlua::Lua::new();
        lua.load(&source)
            .set_name(format!("@{}", path.display()))
            .into_function()
            .map_err(|e| ProjectError::Syntax { id, message: e.to_string() })?;
        let checked =
            check::Checker::default().check_file(&path).map_err(|_| ProjectError::Missing(id, path.clone()))?;
        if checked.has_errors() {
            return Err(ProjectError::Check { id, findings: checked.render() });
        }
        Ok(path)
    }

    /// Export (31): the project's folder copied to the export folder, replacing an older copy.
    pub fn export(&self, id: u16) -> Result<(), ProjectError> {
        copy_project(&self.dir.join(id.to_string()), &self.export.join(id.to_string()))
    }

    /// Import (32): the exported folder copied back into the projects.
    pub fn import(&self, id: u16) -> Result<(), ProjectError> {
        copy_project(&self.export.join(id.to_string()), &self.dir.join(id.to_string()))
    }

    /// Whether project `id` is in the projects folder.
    pub fn has_project(&self, id: u16) -> bool {
        self.main_lua(id).is_file()
    }

    /// Whether project `id` is in the export folder.
    pub fn has_export(&self, id: u16) -> bool {
        self.export.join(id.to_string()).join(MAIN).is_file()
    }
}

/// Copies a project folder (files and subfolders) next to its destination, then swaps it
/// in with a rename: a failed copy leaves the old destination as it was.
fn copy_project(from: &Path, to: &Path) -> Result<(), ProjectError> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |e| ProjectError::Io(path, e)
    };
    let parent = to.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent).map_err(io(parent))?;
    let staging = parent.join(format!(".{}.incoming", to.file_name().and_then(|n| n.to_str()).unwrap_or("project")));
    let _ = std::fs::remove_dir_all(&staging);
    copy_tree(from, &staging)?;
    if to.exists() {
        std::fs::remove_dir_all(to).map_err(io(to))?;
    }
    std::fs::rename(&staging, to).map_err(io(to))
}

fn copy_tree(from: &Path, to: &Path) -> Result<(), ProjectError> {
    std::fs::create_dir_all(to).map_err(|e| ProjectError::Io(to.to_path_buf(), e))?;
    let entries = std::fs::read_dir(from).map_err(|e| ProjectError::Io(from.to_path_buf(), e))?;
    for entry in entries {
        let entry = entry.map_err(|e| ProjectError::Io(from.to_path_buf(), e))?;
        let (source, target) = (entry.path(), to.join(entry.file_name()));
        let kind = entry.file_type().map_err(|e| ProjectError::Io(source.clone(), e))?;
        if kind.is_dir() {
            copy_tree(&source, &target)?;
        } else if kind.is_file() {
            std::fs::copy(&source, &target).map_err(|e| ProjectError::Io(source.clone(), e))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn projects() -> (tempfile::TempDir, Projects) {
        let dir = tempfile::tempdir().unwrap();
        let projects = Projects { dir: dir.path().join("ftp"), export: dir.path().join("usb") };
        (dir, projects)
    }

    fn write(path: &Path, text: &str) {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }

    #[test]
    fn opening_checks_that_main_lua_exists_and_compiles() {
        let (_dir, p) = projects();
        assert!(matches!(p.check(7), Err(ProjectError::Missing(7, _))));
        write(&p.main_lua(7), "my_print('hi')\n");
        assert!(p.check(7).unwrap().ends_with("7/main.lua"));
        write(&p.main_lua(8), "for i = 1 do\n");
        let e = p.check(8).unwrap_err().to_string();
        assert!(e.contains("main.lua:1:") || e.contains("main.lua\"]:1:") || e.contains(":1:"), "{e}");
        // Lua compiles it; the check refuses it before it runs.
        write(&p.main_lua(9), "Enable(0)\nMoveAbsolute(0, 10)\n");
        let e = p.check(9).unwrap_err().to_string();
        assert!(e.contains("main.lua:2:1: error[E101]: unknown global `MoveAbsolute`"), "{e}");
    }

    #[test]
    fn export_and_import_copy_the_whole_folder() {
        let (_dir, p) = projects();
        write(&p.main_lua(3), "local m = require('lib.util')\n");
        write(&p.dir.join("3/lib/util.lua"), "return 1\n");
        p.export(3).unwrap();
        assert!(p.has_export(3));
        assert!(p.export.join("3/lib/util.lua").is_file());
        std::fs::remove_dir_all(p.dir.join("3")).unwrap();
        assert!(!p.has_project(3));
        p.import(3).unwrap();
        assert_eq!(std::fs::read_to_string(p.dir.join("3/lib/util.lua")).unwrap(), "return 1\n");
        assert!(p.export(4).is_err(), "no project 4");
        assert!(!p.export.join("4").exists());
    }
}
