//! Moving a scene file to another directory: the paths of the files it names (a
//! texture, a mesh, a point cloud, a photograph) are relative to the scene file's
//! directory, so a "save as" elsewhere must rewrite them to name the same files.

use serde::{Deserialize, Serialize};
use std::path::{Component, Path};

/// The fields of a scene file that name other files, relative to the scene file's
/// directory: the JSON pointer and the field's name in error messages, for every kind
/// of scene (bend, FFD, slit, photo annotation; each kind has only its own).
pub const SCENE_ASSET_FIELDS: [(&str, &str); 4] = [
    ("/texture", "texture"),
    ("/model/mesh", "model"),
    ("/scan/points", "scan.points"),
    ("/image/path", "image.path"),
];

/// One asset path to rewrite when a scene file moves.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct AssetMove {
    /// JSON pointer of the field (`/texture`, …).
    pub pointer: String,
    /// The field's name (`texture`, `model`, `scan.points`, `image.path`).
    pub field: String,
    /// The path as it is.
    pub from: String,
    /// The path naming the same file from the new directory (`/` separators).
    pub to: String,
}

/// The asset paths of `scene` (any kind of scene file, as parsed JSON) to rewrite when
/// the file moves from directory `from` to directory `to`, both relative to one common
/// root (the editor's served directory) or both absolute: each relative asset path is
/// joined to `from`, normalised lexically (`.` dropped, `..` taken back) and expressed
/// relative to `to`. Absolute asset paths, paths that leave the root (more `..` than
/// `from` is deep) and paths that stay the same are left alone, so the list holds only
/// what changes.
///
/// Lexical, as the editor's paths are: no file is read. Directories one relative and
/// one absolute give no moves.
pub fn relocated_scene_assets(scene: &serde_json::Value, from: &Path, to: &Path) -> Vec<AssetMove> {
    if from.is_absolute() != to.is_absolute() {
        return Vec::new();
    }
    let (Some(from), Some(to)) = (normalised(from), normalised(to)) else {
        return Vec::new();
    };
    SCENE_ASSET_FIELDS
        .iter()
        .filter_map(|&(pointer, field)| {
            let path = scene.pointer(pointer)?.as_str()?;
            if Path::new(path).is_absolute() {
                return None;
            }
            let target = normalised(&Path::new(&from.join("/")).join(path))?;
            let common = target.iter().zip(&to).take_while(|(a, b)| a == b).count();
            let mut parts: Vec<&str> = vec![".."; to.len() - common];
            parts.extend(target[common..].iter().map(String::as_str));
            let moved = parts.join("/");
            (moved != path).then(|| AssetMove {
                pointer: pointer.to_string(),
                field: field.to_string(),
                from: path.to_string(),
                to: moved,
            })
        })
        .collect()
}

/// The components of `path` with `.` dropped and each `..` taking back the component
/// before it; `None` when a `..` would leave the root (or `path` has a prefix, as on
/// Windows). An absolute path keeps its root as an empty first component.
fn normalised(path: &Path) -> Option<Vec<String>> {
    let mut parts: Vec<String> = Vec::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir => {
                if parts.last().is_none_or(String::is_empty) {
                    return None;
                }
                parts.pop();
            }
            Component::Normal(name) => parts.push(name.to_string_lossy().into_owned()),
            Component::RootDir => parts.push(String::new()),
            Component::Prefix(_) => return None,
        }
    }
    Some(parts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn moves(scene: &serde_json::Value, from: &str, to: &str) -> Vec<(String, String)> {
        relocated_scene_assets(scene, Path::new(from), Path::new(to))
            .into_iter()
            .map(|m| (m.field, m.to))
            .collect()
    }

    #[test]
    fn asset_paths_name_the_same_files_from_the_new_directory() {
        let bend = json!({"outline": [], "regions": [], "texture": "textures/grid.png"});
        assert_eq!(
            moves(&bend, "examples", "out/designs"),
            [("texture".to_string(), "../../examples/textures/grid.png".to_string())]
        );
        // Into the directory of the asset, and back to the root.
        assert_eq!(
            moves(&bend, "examples", "examples/textures"),
            [("texture".into(), "grid.png".into())]
        );
        assert_eq!(
            moves(&bend, "examples", ""),
            [("texture".into(), "examples/textures/grid.png".into())]
        );
        // `.` and `..` inside the path are resolved.
        let ffd = json!({"model": {"mesh": "./meshes/../meshes/skirt.obj"}, "deformations": []});
        assert_eq!(moves(&ffd, "a/b", "a"), [("model".into(), "b/meshes/skirt.obj".into())]);
        let slit = json!({"sheet": {}, "scan": {"points": "../scans/chair.ply"}});
        assert_eq!(
            moves(&slit, "a/b", "c"),
            [("scan.points".into(), "../a/scans/chair.ply".into())]
        );
        let photo = json!({"image": {"path": "cup.png", "width": 10, "height": 10}, "curves": []});
        assert_eq!(
            moves(&photo, "photos", "photos/saved"),
            [("image.path".into(), "../cup.png".into())]
        );
        // Absolute directories work the same way.
        assert_eq!(
            moves(&photo, "/home/me/photos", "/home/me/other"),
            [("image.path".into(), "../photos/cup.png".into())]
        );
    }

    #[test]
    fn what_need_not_or_cannot_move_is_left_alone() {
        let bend = json!({"texture": "textures/grid.png"});
        // The same directory, written differently.
        assert!(moves(&bend, "examples", "./examples/../examples").is_empty());
        // An absolute asset path, a path that leaves the root, a directory that does.
        assert!(moves(&json!({"texture": "/srv/grid.png"}), "a", "b").is_empty());
        assert!(moves(&json!({"texture": "../../grid.png"}), "a", "b").is_empty());
        assert!(moves(&bend, "../a", "b").is_empty());
        assert!(moves(&bend, "/srv/a", "b").is_empty());
        // No asset, or a field that is not a string (the scene parser reports those).
        assert!(moves(&json!({"model": {"procedural": {"kind": "duct"}}}), "a", "b").is_empty());
        assert!(moves(&json!({"texture": 3}), "a", "b").is_empty());
    }
}
