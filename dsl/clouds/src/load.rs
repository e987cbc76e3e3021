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

fn check_name(file: &Path, name: &str) -> Result<(), DataError> {
    let stem = file
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or_default();
    if name.is_empty()
        || !name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-')
    {
        return Err(DataError::invalid(
            file,
            "name",
            format!("must be lowercase letters, digits and '-', got `{name}`"),
        ));
    }
    if name != stem {
        return Err(DataError::invalid(
            file,
            "name",
            format!("must match the file name `{stem}`, got `{name}`"),
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
    s.validate()
        .map_err(|(f, r)| DataError::invalid(file, f, r))?;
    Ok(s)
}

/// Reads a scene preset file.
pub fn load_scene(file: &Path) -> Result<ScenePreset, DataError> {
    parse_scene(file, &read(file)?)
}

/// Every genus and scene preset of a data folder (`genera/*.toml`, `scenes/*.toml`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CloudLibrary {
    pub genera: BTreeMap<String, (PathBuf, Genus)>,
    pub scenes: BTreeMap<String, (PathBuf, ScenePreset)>,
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
    pub fn load(dir: &Path) -> Result<CloudLibrary, DataError> {
        let mut lib = CloudLibrary::default();
        for file in toml_files(&dir.join("genera"))? {
            let g = load_genus(&file)?;
            lib.genera.insert(g.name.clone(), (file, g));
        }
        let scenes = dir.join("scenes");
        if scenes.is_dir() {
            for file in toml_files(&scenes)? {
                let s = load_scene(&file)?;
                if !lib.genera.contains_key(&s.genus) {
                    return Err(DataError::UnknownReference {
                        file,
                        kind: "genus",
                        name: s.genus.clone(),
                        known: lib.genera.keys().cloned().collect::<Vec<_>>().join(", "),
                    });
                }
                lib.scenes.insert(s.name.clone(), (file, s));
            }
        }
        Ok(lib)
    }

    pub fn genus(&self, name: &str) -> Option<&Genus> {
        self.genera.get(name).map(|(_, g)| g)
    }
}
