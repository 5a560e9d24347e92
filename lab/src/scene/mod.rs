//! Scene files: the lab's side of the scene crate's TOML schema
//! ([`linesample_scene::schema`], whose docs give the format of every
//! effect and every error it reports). Here a file is read
//! ([`SceneSource`], kept in a run's manifest so that a resumed run refuses
//! a changed file, and [`load`]) and named by its path; the parser and the
//! checked model are the scene crate's, re-exported.

use std::path::Path;

use serde::{Deserialize, Serialize};

pub use linesample_scene::ao::world::ao_lines;
pub use linesample_scene::camera::Camera;
pub use linesample_scene::model::{
    BoxDef, CausticScene, EffectParams, Estimators, FluenceDef, Hit, LightDef, Orientation,
    QuadDef, Scene, SphereDef,
};
pub use linesample_scene::schema::{EffectKind, SceneError, SceneFile};

pub use crate::spec::{CentrePdf, Primitive, SceneSampler};

/// Volumetric-caustic scene files ([`linesample_scene::schema::caustic`]).
pub mod caustic {
    use std::path::Path;

    pub use linesample_scene::model::{CausticScene, FluenceDef};
    pub use linesample_scene::schema::caustic::KIND_NAME;

    use super::SceneError;

    /// Checks the text of a volumetric-caustic scene file (`path` names it
    /// in errors).
    ///
    /// # Errors
    /// A [`SceneError`] naming the file, line, column and field.
    pub fn parse(path: &Path, text: &str) -> Result<CausticScene, SceneError> {
        linesample_scene::schema::caustic::parse(&path.display().to_string(), text)
    }
}

/// A scene file as read, so that a resumed run refuses a changed file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneSource {
    pub path: String,
    pub text: String,
}

impl SceneSource {
    /// Reads the file at `path`.
    ///
    /// # Errors
    /// The file cannot be read.
    pub fn read(path: &Path) -> crate::Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(SceneSource {
            path: path.display().to_string(),
            text,
        })
    }

    /// The checked scene (camera effects).
    ///
    /// # Errors
    /// The scene file's error.
    pub fn scene(&self) -> crate::Result<Scene> {
        parse(Path::new(&self.path), &self.text)
            .map_err(|e| crate::LabError::Message(e.to_string()))
    }

    /// The checked volumetric-caustic scene.
    ///
    /// # Errors
    /// The scene file's error.
    pub fn caustic(&self) -> crate::Result<CausticScene> {
        caustic::parse(Path::new(&self.path), &self.text)
            .map_err(|e| crate::LabError::Message(e.to_string()))
    }

    /// The checked scene, whatever its effect.
    ///
    /// # Errors
    /// The scene file's error.
    pub fn any(&self) -> Result<SceneFile, SceneError> {
        parse_any(Path::new(&self.path), &self.text)
    }
}

/// Reads and checks a scene file.
///
/// # Errors
/// A [`SceneError`] naming the file, line, column and field.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let text = std::fs::read_to_string(path).map_err(|e| SceneError {
        file: path.display().to_string(),
        line: 0,
        column: 0,
        field: "(file)".into(),
        message: format!("cannot read it: {e}"),
    })?;
    parse(path, &text)
}

/// Reads `[effect] kind` alone ([`linesample_scene::schema::effect_kind`]).
///
/// # Errors
/// As [`linesample_scene::schema::effect_kind`].
pub fn effect_kind(path: &Path, text: &str) -> Result<EffectKind, SceneError> {
    linesample_scene::schema::effect_kind(&path.display().to_string(), text)
}

/// Checks the text of a scene file of any effect
/// ([`linesample_scene::schema::parse_any`]; `path` names it in errors).
///
/// # Errors
/// A [`SceneError`] naming the file, line, column and field.
pub fn parse_any(path: &Path, text: &str) -> Result<SceneFile, SceneError> {
    linesample_scene::schema::parse_any(&path.display().to_string(), text)
}

/// Checks the text of a camera scene file
/// ([`linesample_scene::schema::parse`]; `path` names it in errors).
///
/// # Errors
/// A [`SceneError`] naming the file, line, column and field.
pub fn parse(path: &Path, text: &str) -> Result<Scene, SceneError> {
    linesample_scene::schema::parse(&path.display().to_string(), text)
}
