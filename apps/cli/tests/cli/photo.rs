//! `sheetform photo`: the examples, bad input.

use crate::common::{ezdxf_cut, obj_isometry_error, read_obj, repo, report, sheetform, validate_glb};

#[test]
fn photo_examples_are_reconstructed_with_every_output() {
    for annotation in [
        "examples/photo/coffee-cup.json",
        "examples/photo/coffee-cup.svg",
        "examples/photo/synthetic/cone-ortho.json",
    ] {
        let tmp = tempfile::tempdir().unwrap();
        let o = sheetform(&[
            "photo",
            repo().join(annotation).to_str().unwrap(),
            "-o",
            tmp.path().to_str().unwrap(),
        ]);
        assert!(
            o.status.success(),
            "{annotation}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let r = report(tmp.path());
        assert_eq!(r["command"], "photo");
        assert_eq!(r["status"], "ok", "{annotation}");
        let photo = &r["photo"];
        assert_eq!(
            photo["patch_count"], 1,
            "{annotation}: the body; the mouth is an opening"
        );
        assert_eq!(photo["opening_count"], 1);
        assert!(photo["ruling_count"].as_u64().unwrap() >= 20);
        assert!(photo["symmetric_pair_count"].as_u64().unwrap() >= 20);
        // The paper's metric, after its linear solve and after the refinement (degrees).
        assert!(photo["developability_error_linear"]["mean_deg"].as_f64().unwrap() < 6.0);
        assert!(photo["developability_error_refined"]["mean_deg"].as_f64().unwrap() <= 0.1);
        assert!(photo["reprojection_error_max_px"].as_f64().unwrap() < 2.0);
        // The body is a ruled strip: it unfolds exactly, and model.obj's vt is that pattern.
        let obj = read_obj(&tmp.path().join("model.obj"));
        assert!(
            obj_isometry_error(&obj) < 1e-9,
            "{annotation}: vt is the flat pattern at 1:1"
        );
        validate_glb(&[tmp.path().join("model.glb")]);
        let dxf = ezdxf_cut(&tmp.path().join("pattern.dxf"));
        assert_eq!(dxf["errors"], 0);
        assert_eq!(dxf["count"], 1, "one piece");
        // The pattern's area is the model's (mm²).
        let area = dxf["area"].as_f64().unwrap().abs();
        let model_area = r["area_mm2"].as_f64().unwrap();
        assert!(
            (area / model_area - 1.0).abs() < 0.02,
            "{annotation}: {area} vs {model_area}"
        );
        // A drawing from Inkscape also leaves the annotation it was read as.
        let converted = tmp.path().join("annotation.json");
        assert_eq!(converted.exists(), annotation.ends_with(".svg"), "{annotation}");
        if converted.exists() {
            let text = std::fs::read_to_string(&converted).unwrap();
            let json: serde_json::Value = serde_json::from_str(&text).unwrap();
            assert_eq!(json["curves"].as_array().unwrap().len(), 4);
        }
        let overlay = std::fs::read_to_string(tmp.path().join("overlay.svg")).unwrap();
        for layer in ["patches", "rulings", "symmetry", "curves", "reprojected"] {
            assert!(overlay.contains(&format!("id=\"{layer}\"")), "{layer}");
        }
        assert!(overlay.contains("data:image/png;base64,"));
        // Every ruling; mirror pairs thinned to at most 60 so the photo shows.
        let pairs = photo["symmetric_pair_count"].as_u64().unwrap() as usize;
        assert_eq!(
            overlay.matches("class=\"ruling\"").count(),
            photo["ruling_count"].as_u64().unwrap() as usize
        );
        assert_eq!(
            overlay.matches("class=\"pair\"").count(),
            pairs.div_ceil(pairs.div_ceil(60).max(1))
        );
        // The PNG overlay: the photo's size, and not the photo alone (curves drawn on it).
        let png = std::fs::read(tmp.path().join("overlay.png")).unwrap();
        assert_eq!(&png[1..4], b"PNG");
        let (w, h) = (
            u32::from_be_bytes([png[16], png[17], png[18], png[19]]),
            u32::from_be_bytes([png[20], png[21], png[22], png[23]]),
        );
        let expected: (u32, u32) = if annotation.contains("coffee") {
            (600, 400)
        } else {
            (480, 480)
        };
        assert_eq!((w, h), expected);
    }
}

#[test]
fn photo_bad_input_is_an_error_and_writes_nothing() {
    let good: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(repo().join("examples/photo/synthetic/cone-ortho.json")).unwrap(),
    )
    .unwrap();
    let cases: Vec<(serde_json::Value, &str)> = vec![
        (
            {
                let mut v = good.clone();
                v["image"]["path"] = "missing.png".into();
                v
            },
            "missing.png",
        ),
        (
            {
                let mut v = good.clone();
                v["image"]["width"] = 481.into();
                v
            },
            "480 × 480",
        ),
        (
            {
                let mut v = good.clone();
                v["true_size"]["length"] = 0.into();
                v
            },
            "true_size.length",
        ),
    ];
    for (value, expect) in cases {
        let tmp = tempfile::tempdir().unwrap();
        // The image path is relative to the annotation: write it next to the example's PNG.
        let file = repo().join("examples/photo/synthetic").join(format!(
            ".bad-{}.json",
            tmp.path().file_name().unwrap().to_string_lossy()
        ));
        std::fs::write(&file, value.to_string()).unwrap();
        let out = tmp.path().join("out");
        let o = sheetform(&["photo", file.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        std::fs::remove_file(&file).unwrap();
        assert_eq!(o.status.code(), Some(1), "{expect}");
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(stderr.contains(expect), "{expect}: {stderr}");
        assert!(!out.exists(), "nothing written");
    }
    let o = sheetform(&["schema", "photo"]);
    assert!(o.status.success());
    let printed: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let file = "docs/schema/photo-annotation.schema.json";
    let documented: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(repo().join(file)).unwrap()).unwrap();
    assert_eq!(
        printed, documented,
        "{file} is stale: regenerate with `sheetform schema photo > {file}`"
    );
}
