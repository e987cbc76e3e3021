//! Loading genus and scene files. Parsing goes through `serde_path_to_error`, so a wrong type or
//! an unknown key is reported with its exact path (`layers[1].height`); semantic checks follow.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;

use super::error::DataError;
use super::genus::Genus;
use super::scene::ScenePreset;

fn parse<T: DeserializeOwned>(file: &Path, text: &str) -> Result<T, DataError> {
    let de = toml::Deserializer::parse(text).map_err(|e| syntax_error(file, text, &e))?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let field = e.path().to_string();
        let field = if field == "." {
            "(top level)".to_string()
        } else {
            field
        };
        DataError::invalid(file, field, first_line(e.inner().message()))
    })
}

fn first_line(s: &str) -> String {
    // toml's messages end with a source excerpt; the first line is the reason.
    let s = s.trim();
    s.lines()
        .find(|l| !l.trim().is_empty() && !l.starts_with("TOML parse error"))
        .unwrap_or(s)
        .trim()
        .to_string()
}

fn syntax_error(file: &Path, text: &str, e: &toml::de::Error) -> DataError {
    let field = match e.span() {
        Some(span) => {
            let line = text[..span.start.min(text.len())].matches('\n').count() + 1;
            format!("line {line}")
        }
        None => "(syntax)".to_string(),
    };
    DataError::invalid(
        file,
        field,
        format!("TOML syntax: {}", first_line(e.message())),
    )
}

fn read(file: &Path) -> Result<String, DataError> {
    std::fs::read_to_string(file).map_err(|e| DataError::Read {
        file: file.to_path_buf(),
        reason: e.to_string(),
    })
}

/// Whether `name` is a valid genus or scene name: lowercase ASCII letters, digits and '-'.
fn valid_name(name: &str) -> bool {
    !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-')
}

/// `name` made valid: lowercased, anything else than letters and digits turned into '-'.
fn suggested_name(name: &str) -> String {
    let s: String = name
        .trim()
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    let s = s.trim_matches('-').to_string();
    if s.is_empty() { "my-clouds".into() } else { s }
}

/// A file's `name` must be a valid name and equal its file name (stem), so that what a scene
/// or a flag names is found by file name; the error says which to change, and to what.
fn check_name(file: &Path, name: &str) -> Result<(), DataError> {
    let stem = file
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or_default();
    let ext = file.extension().and_then(|s| s.to_str()).unwrap_or("toml");
    if !valid_name(stem) {
        let better = suggested_name(if valid_name(name) { name } else { stem });
        return Err(DataError::invalid(
            file,
            "name",
            format!(
                "the file name `{stem}` is not a valid name (lowercase letters, digits and '-'); \
                 rename the file to `{better}.{ext}` and set name = \"{better}\""
            ),
        ));
    }
    if !valid_name(name) {
        return Err(DataError::invalid(
            file,
            "name",
            format!(
                "must be lowercase letters, digits and '-', got `{name}`; set name = \"{stem}\" \
                 to match the file name"
            ),
        ));
    }
    if name != stem {
        return Err(DataError::invalid(
            file,
            "name",
            format!(
                "`{name}` does not match the file name `{stem}`; set name = \"{stem}\", or \
                 rename the file to `{name}.{ext}`"
            ),
        ));
    }
    Ok(())
}

/// Parses and validates a genus from text (`file` names it in errors).
pub fn parse_genus(file: &Path, text: &str) -> Result<Genus, DataError> {
    let g: Genus = parse(file, text)?;
    check_name(file, &g.name)?;
    g.validate()
        .map_err(|(f, r)| DataError::invalid(file, f, r))?;
    Ok(g)
}

/// Reads a genus file.
pub fn load_genus(file: &Path) -> Result<Genus, DataError> {
    parse_genus(file, &read(file)?)
}

/// Parses and validates a scene preset from text.
pub fn parse_scene(file: &Path, text: &str) -> Result<ScenePreset, DataError> {
    let s: ScenePreset = parse(file, text)?;
    check_name(file, &s.name)?;
    s.validate(file)?;
    Ok(s)
}

/// Reads a scene preset file.
pub fn load_scene(file: &Path) -> Result<ScenePreset, DataError> {
    parse_scene(file, &read(file)?)
}

/// Every genus and scene preset of a data folder (`genera/*.toml`, `scenes/*.toml`). A file
/// that fails to load does not stop the others: it is kept in [`CloudLibrary::problems`], so
/// commands about other genera run, and one that names it gets its error.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CloudLibrary {
    pub genera: BTreeMap<String, (PathBuf, Genus)>,
    pub scenes: BTreeMap<String, (PathBuf, ScenePreset)>,
    /// The files that could not be loaded, each with its error.
    pub problems: Vec<DataError>,
}

fn toml_files(dir: &Path) -> Result<Vec<PathBuf>, DataError> {
    let entries = std::fs::read_dir(dir).map_err(|e| DataError::Read {
        file: dir.to_path_buf(),
        reason: e.to_string(),
    })?;
    let mut files: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    Ok(files)
}

impl CloudLibrary {
    /// Loads `dir/genera/*.toml` and `dir/scenes/*.toml` (a missing `scenes` folder is empty).
    /// Fails only when `dir/genera` cannot be read; a bad file is kept in `problems`.
    pub fn load(dir: &Path) -> Result<CloudLibrary, DataError> {
        let mut lib = CloudLibrary::default();
        for file in toml_files(&dir.join("genera"))? {
            match load_genus(&file) {
                Ok(g) => {
                    lib.genera.insert(g.name.clone(), (file, g));
                }
                Err(e) => lib.problems.push(e),
            }
        }
        let scenes = dir.join("scenes");
        if scenes.is_dir() {
            for file in toml_files(&scenes)? {
                let s = match load_scene(&file) {
                    Ok(s) => s,
                    Err(e) => {
                        lib.problems.push(e);
                        continue;
                    }
                };
                let named =
                    std::iter::once(&s.genus).chain(s.weather.iter().flat_map(|w| &w.genus));
                if let Some(missing) = named.into_iter().find(|g| !lib.genera.contains_key(*g)) {
                    lib.problems.push(lib.missing_genus(&file, missing));
                    continue;
                }
                lib.scenes.insert(s.name.clone(), (file, s));
            }
        }
        Ok(lib)
    }

    pub fn genus(&self, name: &str) -> Option<&Genus> {
        self.genera.get(name).map(|(_, g)| g)
    }

    /// The genus `name`, or why there is none: the error of its file when that failed to load
    /// (`genera/<name>.toml`), else an unknown name with the known ones (`file` is who asked).
    pub fn require_genus(&self, file: &Path, name: &str) -> Result<&Genus, DataError> {
        self.genus(name)
            .ok_or_else(|| self.missing_genus(file, name))
    }

    fn missing_genus(&self, file: &Path, name: &str) -> DataError {
        if let Some(e) = self.problem_of(name) {
            return e.clone();
        }
        DataError::UnknownReference {
            file: file.to_path_buf(),
            kind: "genus",
            name: name.to_string(),
            known: self.genera.keys().cloned().collect::<Vec<_>>().join(", "),
        }
    }

    /// The load error of the genus file named `name` (`genera/<name>.toml`), if it had one.
    pub fn problem_of(&self, name: &str) -> Option<&DataError> {
        self.problems.iter().find(|e| {
            e.file().is_some_and(|f| {
                f.file_stem().is_some_and(|s| s == name)
                    && f.parent()
                        .and_then(Path::file_name)
                        .is_some_and(|d| d == "genera")
            })
        })
    }
}
