//! Where the genus and scene files come from, and how command-line flags pick a variant.

use std::path::{Path, PathBuf};

use nimbus_codegen::{
    CodegenError, VariantSource, catalog, cloud_catalog, cloud_variant, select_variants,
};
use nimbus_dsl::cloud::{CloudLibrary, Genus, Quality, ScenePreset, Toggle, load_scene};

/// The data folder: `--data`, else `NIMBUS_DATA`, else this repository's `examples/`.
pub(crate) fn data_dir(flag: Option<&Path>) -> PathBuf {
    flag.map(Path::to_path_buf)
        .or_else(|| std::env::var_os("NIMBUS_DATA").map(PathBuf::from))
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples"))
}

pub(crate) fn load(flag: Option<&Path>) -> Result<CloudLibrary, CodegenError> {
    Ok(CloudLibrary::load(&data_dir(flag))?)
}

/// A scene file and the library genus it names (an unknown genus is an error naming the file).
pub(crate) fn scene_with_genus<'a>(
    lib: &'a CloudLibrary,
    file: &Path,
) -> Result<(ScenePreset, &'a Genus), Box<dyn std::error::Error>> {
    let scene = load_scene(file)?;
    let genus = lib.genus(&scene.genus).ok_or_else(|| {
        format!(
            "{}: genus `{}` is not in the library",
            file.display(),
            scene.genus
        )
    })?;
    Ok((scene, genus))
}

pub(crate) fn parse_toggles(list: &[String]) -> Result<Vec<Toggle>, CodegenError> {
    let mut out = Vec::new();
    for item in list
        .iter()
        .flat_map(|s| s.split(','))
        .map(str::trim)
        .filter(|s| !s.is_empty())
    {
        let t = Toggle::parse(item).ok_or_else(|| CodegenError::Unknown {
            kind: "toggle",
            given: item.to_string(),
            known: Toggle::ALL.map(Toggle::name).join(", "),
        })?;
        out.push(t);
    }
    Ok(out)
}

/// What the user asked to emit or check.
pub(crate) struct Selection<'a> {
    pub name: Option<&'a str>,
    pub genus: Option<&'a str>,
    pub quality: Option<&'a str>,
    pub enable: &'a [String],
    pub disable: &'a [String],
    pub octaves: Option<u32>,
}

pub(crate) fn resolve(
    sel: &Selection<'_>,
    lib: &CloudLibrary,
) -> Result<Vec<VariantSource>, CodegenError> {
    let quality = match sel.quality {
        Some(q) => Some(Quality::parse(q).ok_or_else(|| CodegenError::Unknown {
            kind: "quality preset",
            given: q.to_string(),
            known: Quality::ALL.map(Quality::name).join(", "),
        })?),
        None => None,
    };
    let enable = parse_toggles(sel.enable)?;
    let disable = parse_toggles(sel.disable)?;
    if let Some(o) = sel.octaves
        && !(1..=12).contains(&o)
    {
        return Err(CodegenError::Unknown {
            kind: "octave count",
            given: o.to_string(),
            known: "1..=12".into(),
        });
    }
    if let Some(genus) = sel.genus {
        let qualities = quality.map_or_else(|| Quality::ALL.to_vec(), |q| vec![q]);
        let mut out = Vec::new();
        for q in qualities {
            let v = cloud_variant(lib, genus, q, |f| {
                for t in &enable {
                    t.set(f, true);
                }
                for t in &disable {
                    t.set(f, false);
                }
                if let Some(o) = sel.octaves {
                    f.octaves = o;
                }
            })
            .ok_or_else(|| CodegenError::Unknown {
                kind: "genus",
                given: genus.to_string(),
                known: lib.genera.keys().cloned().collect::<Vec<_>>().join(", "),
            })?;
            out.push(v);
        }
        return Ok(out);
    }
    if !enable.is_empty() || !disable.is_empty() || quality.is_some() || sel.octaves.is_some() {
        return Err(CodegenError::Unknown {
            kind: "combination",
            given: "--quality/--enable/--disable/--octaves without --genus".into(),
            known: "pass --genus NAME with them".into(),
        });
    }
    match sel.name {
        Some(n) => select_variants(n, Some(lib)),
        None => {
            let mut all = catalog();
            all.extend(cloud_catalog(lib));
            Ok(all)
        }
    }
}
