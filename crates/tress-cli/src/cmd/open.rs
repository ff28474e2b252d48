//! Opening a scene for drawing: every subcommand that renders (`render`, `compare`, `bench`,
//! `view`) gets its [`Session`] from here, with the CLI's SATF databases.

use std::cell::RefCell;
use std::path::PathBuf;
use std::rc::Rc;

use anyhow::Result;
use tress_render::scene_setup::SatfScene;
use tress_render::session::{DatabaseLoader, Session, SessionOptions};
use tress_render::{GpuContext, TargetFormats};
use tress_scene::Scene;

use super::satf_bake::database_for_render;

/// The file the session's SATF database was last read from (or baked into), for the report.
#[derive(Clone, Debug, Default)]
pub(crate) struct DatabaseFile(Rc<RefCell<Option<PathBuf>>>);

impl DatabaseFile {
    /// The file, once the `satf` technique has loaded its database.
    pub(crate) fn path(&self) -> Option<PathBuf> {
        self.0.borrow().clone()
    }
}

/// The SATF database of a scene's settings: its file, baked there (or in the cache folder) on
/// first use ([`database_for_render`]); the file read is recorded in `file`.
pub(crate) fn satf_loader(file: Option<&DatabaseFile>) -> DatabaseLoader {
    let file = file.cloned();
    Box::new(move |s: &SatfScene| {
        let (db, path) = database_for_render(s.database.as_deref(), &s.bake, s.bake_explicit)?;
        if let Some(f) = &file {
            *f.0.borrow_mut() = Some(path);
        }
        Ok(db)
    })
}

/// A session on `scene` with `overrides` (applied again after framing, so they win over it),
/// framed on its hair or cards when `auto_frame`; SATF databases as [`satf_loader`] finds them.
pub(crate) fn open_session(
    ctx: &GpuContext,
    scene: &Scene,
    auto_frame: bool,
    overrides: Vec<String>,
    database: Option<&DatabaseFile>,
) -> Result<Session> {
    let options = SessionOptions {
        auto_frame,
        overrides,
        satf_database: Some(satf_loader(database)),
        ..SessionOptions::default()
    };
    Ok(Session::new(
        ctx,
        TargetFormats::default(),
        scene.clone(),
        options,
    )?)
}
