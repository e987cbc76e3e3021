//! A scene file as every command reads it. `render`, `explain`, `emit --scene`, `animate`,
//! `export-density`, `gallery` and `tradeoff` all load a scene here and take it at a time of its
//! timeline here, so a scene means one thing whichever command reads it: the sun by its
//! `[clock]`, the clouds by its `[wind]`, the genus and coverage by its `[[weather]]` states.
//! Every genus the scene names (its own and each weather state's) is found when the file is
//! loaded, so an unknown one is an error naming the file, whichever command meets it first.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use nimbus_clouds::wind::Drift;
use nimbus_clouds::{CloudLibrary, DataError, Genus, ScenePreset, load_genus, load_scene};

use nimbus_runtime::render::Frame;
use nimbus_runtime::scene_time::scenes_at;

use crate::error::CliError;

/// The library a scene's genus names refer to: `--data`, else `$NIMBUS_DATA`, else the folder
/// above the scene's `scenes/` when it has `genera/`, else the built-in examples.
pub(crate) fn library_for(
    data: Option<&Path>,
    scene: Option<&Path>,
) -> Result<CloudLibrary, CliError> {
    if data.is_none() && std::env::var_os("NIMBUS_DATA").is_none() {
        let beside = scene
            .and_then(Path::parent)
            .and_then(Path::parent)
            .filter(|d| d.join("genera").is_dir());
        if let Some(dir) = beside {
            return crate::data::load_dir(dir);
        }
    }
    crate::data::load(data)
}

/// Whether a genus name is a genus file's path rather than a library name.
fn is_path(name: &str) -> bool {
    name.ends_with(".toml") || name.contains('/')
}

/// The genus `name` names: a genus file's path, or a library genus (its file's load error when
/// that file failed to load); `None` when the library has no such name.
fn find_genus(lib: &CloudLibrary, name: &str) -> Result<Option<Genus>, CliError> {
    if is_path(name) {
        return Ok(Some(load_genus(Path::new(name))?));
    }
    if let Some(g) = lib.genus(name) {
        return Ok(Some(g.clone()));
    }
    match lib.problem_of(name) {
        Some(problem) => Err(problem.clone().into()),
        None => Ok(None),
    }
}

fn known(lib: &CloudLibrary) -> String {
    lib.genera.keys().cloned().collect::<Vec<_>>().join(", ")
}

/// A genus named on the command line (`--genus`): a library name or a genus file's path.
pub(crate) fn genus_of(lib: &CloudLibrary, name: &str) -> Result<Genus, CliError> {
    find_genus(lib, name)?.ok_or_else(|| CliError::Unknown {
        kind: "genus",
        given: name.to_string(),
        known: known(lib),
    })
}

/// A genus named in `file` (field `what`): an unknown name is an error naming the file.
fn genus_in_file(
    lib: &CloudLibrary,
    file: &Path,
    what: &'static str,
    name: &str,
) -> Result<Genus, CliError> {
    find_genus(lib, name)?.ok_or_else(|| {
        DataError::UnknownReference {
            file: file.to_path_buf(),
            kind: what,
            name: name.to_string(),
            known: known(lib),
        }
        .into()
    })
}

/// A loaded scene file with every genus it names.
pub(crate) struct SceneInput {
    pub file: PathBuf,
    pub scene: ScenePreset,
    /// Every genus the scene names, by the name it uses (a `--genus` given in its place stands
    /// for all of them).
    genera: BTreeMap<String, Genus>,
    /// `--genus`: replaces the scene's genus (and its weather states') everywhere.
    replacement: Option<Genus>,
}

/// The scene at one time: what one picture of it shows, and that picture's weight in the blend
/// (one state, weight 1; or two while one genus gives way to another).
#[derive(Clone)]
pub(crate) struct SceneState {
    /// The scene with the sun by its clock, and the genus and coverage of the weather.
    pub scene: ScenePreset,
    /// The genus, its coverage the weather's (or the scene's).
    pub genus: Genus,
    pub drift: Drift,
    pub weight: f32,
}

impl SceneState {
    /// The frame of this state at `width`×`height`, drifted by the wind.
    pub(crate) fn frame(&self, width: u32, height: u32) -> Frame {
        let mut f = Frame::from_scene(&self.scene, &self.genus, width, height);
        f.wind = self.drift;
        f
    }
}

impl SceneInput {
    /// Loads `file` with the library it refers to ([`library_for`]); `genus` (the `--genus`
    /// flag) replaces the scene's genus.
    pub(crate) fn load(
        data: Option<&Path>,
        file: &Path,
        genus: Option<&str>,
    ) -> Result<SceneInput, CliError> {
        let lib = library_for(data, Some(file))?;
        Self::load_with(&lib, file, genus)
    }

    /// Loads `file` whose genus names refer to `lib`.
    pub(crate) fn load_with(
        lib: &CloudLibrary,
        file: &Path,
        genus: Option<&str>,
    ) -> Result<SceneInput, CliError> {
        Self::from_scene(lib, file, load_scene(file)?, genus)
    }

    /// A scene already parsed from `file`, whose genus names refer to `lib`.
    pub(crate) fn from_scene(
        lib: &CloudLibrary,
        file: &Path,
        scene: ScenePreset,
        genus: Option<&str>,
    ) -> Result<SceneInput, CliError> {
        let replacement = genus.map(|g| genus_of(lib, g)).transpose()?;
        let mut genera = BTreeMap::new();
        if replacement.is_none() {
            let own = genus_in_file(lib, file, "genus", &scene.genus)?;
            genera.insert(scene.genus.clone(), own);
            for state in &scene.weather {
                if let Some(name) = &state.genus
                    && !genera.contains_key(name)
                {
                    let g = genus_in_file(lib, file, "genus of a [[weather]] state", name)?;
                    genera.insert(name.clone(), g);
                }
            }
        }
        Ok(SceneInput {
            file: file.to_path_buf(),
            scene,
            genera,
            replacement,
        })
    }

    /// The genus the scene calls `name` (every name the scene uses was found at load).
    fn genus(&self, name: &str) -> Option<&Genus> {
        self.replacement.as_ref().or_else(|| self.genera.get(name))
    }

    /// The scene at `seconds` ([`nimbus_clouds::timeline`]): one state, or two weighted while
    /// one genus gives way to another. Without a timeline, the scene as written.
    pub(crate) fn at(&self, seconds: f64) -> Result<Vec<SceneState>, CliError> {
        let coverage = |name: &str| self.genus(name).map_or(0.0, |g| g.coverage);
        let mut states = Vec::new();
        for (scene, drift, weight) in scenes_at(&self.scene, &coverage, seconds) {
            let Some(genus) = self.genus(&scene.genus) else {
                // Every name was found at load; a name the timeline made up is Nimbus's bug.
                return Err(CliError::Unknown {
                    kind: "genus of the timeline",
                    given: scene.genus,
                    known: self.genera.keys().cloned().collect::<Vec<_>>().join(", "),
                });
            };
            let mut genus = genus.clone();
            genus.coverage = scene.coverage.unwrap_or(genus.coverage);
            states.push(SceneState {
                scene,
                genus,
                drift,
                weight,
            });
        }
        Ok(states)
    }

    /// The one state at `seconds`; `command` names what cannot take a blend of two genera.
    pub(crate) fn single_at(
        &self,
        seconds: f64,
        command: &'static str,
    ) -> Result<SceneState, CliError> {
        let mut states = self.at(seconds)?;
        if states.len() > 1 {
            return Err(CliError::Refused {
                what: command,
                given: format!(
                    "{}: second {seconds}, while {} gives way to {}",
                    self.file.display(),
                    states[0].genus.name,
                    states[1].genus.name
                ),
                accepted: "a time at which one weather state holds (or changes within its genus)"
                    .into(),
            });
        }
        Ok(states.remove(0))
    }
}
