//! Pattern outputs read back by outside tools: DXF (ezdxf), PDF (pdftoppm), scales, units, sheets.

use crate::common::{ezdxf_cut, repo, report, shared, sheetform};
use std::process::Command;

#[test]
fn a_piece_larger_than_the_sheet_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = sheetform(&[
        "flatten",
        shared("crumpled-developable.obj").to_str().unwrap(),
        "--units",
        "cm",
        "--scale",
        "5",
        "--sheet",
        "50x50",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("piece `crumpled-developable`") && err.contains("does not fit"),
        "{err}"
    );
    assert!(!out.exists());
}

#[test]
fn patterns_are_readable_and_at_true_scale_in_dxf_and_pdf() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = repo().join("examples/sheet-with-hole.json");
    let o = sheetform(&[
        "bend",
        scene.to_str().unwrap(),
        "-o",
        tmp.path().to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(tmp.path());
    let flat_area = r["flat_area_mm2"].as_f64().unwrap();
    let d = ezdxf_cut(&tmp.path().join("pattern.dxf"));
    assert_eq!(d["errors"], 0, "{d}");
    assert_eq!(d["closed"], true);
    assert_eq!(d["count"], 2, "outline and one hole: {d}");
    assert_eq!(d["insunits"], 4, "millimetres");
    assert_eq!(d["measurement"], 1, "metric, as the units say");
    assert_eq!(d["fixes"], 0, "ezdxf repairs nothing: {d}");
    // The extents frame the pattern (its cut outline here).
    let extent = |k: &str, i: usize| d[k][i].as_f64().unwrap();
    assert!(
        (extent("extmax", 0) - extent("extmin", 0) - d["width"].as_f64().unwrap()).abs() < 1e-6
            && (extent("extmax", 1) - extent("extmin", 1) - d["height"].as_f64().unwrap()).abs() < 1e-6,
        "{d}"
    );
    assert!(d["folds"].as_u64().unwrap() > 10);
    for layer in ["CUT", "FOLD", "LABEL"] {
        assert!(d["layers"].as_array().unwrap().iter().any(|l| l == layer), "{d}");
    }
    // Outline counter-clockwise, hole clockwise: the signed sum is the sheet's area.
    assert!(
        (d["area"].as_f64().unwrap() - flat_area).abs() <= 1e-6 * flat_area,
        "{d} vs {flat_area}"
    );
    assert!(
        (d["width"].as_f64().unwrap() - 300.0).abs() < 1e-6 && (d["height"].as_f64().unwrap() - 140.0).abs() < 1e-6,
        "{d}"
    );
    // The PDF renders, one page per tile that shows the pattern, A4.
    let pages = r["pattern"]["page_count"].as_u64().unwrap();
    let tiles = r["pattern"]["tile_rows"].as_u64().unwrap() * r["pattern"]["tile_columns"].as_u64().unwrap();
    assert!(pages >= 1 && pages <= tiles);
    let render = Command::new("pdftoppm")
        .args(["-r", "10", "-png"])
        .arg(tmp.path().join("pattern.pdf"))
        .arg(tmp.path().join("page"))
        .output()
        .expect("pdftoppm runs");
    assert!(render.status.success(), "{}", String::from_utf8_lossy(&render.stderr));
    let rendered = std::fs::read_dir(tmp.path())
        .unwrap()
        .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().starts_with("page"))
        .count();
    assert_eq!(rendered as u64, pages);
    let info = Command::new("pdfinfo")
        .arg(tmp.path().join("pattern.pdf"))
        .output()
        .expect("pdfinfo runs");
    assert!(
        String::from_utf8_lossy(&info.stdout).contains("595.276 x 841.89"),
        "{}",
        String::from_utf8_lossy(&info.stdout)
    );
}

#[test]
fn pattern_scale_units_and_paper_options() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = repo().join("examples/bent-rectangle.json");
    let o = sheetform(&[
        "bend",
        scene.to_str().unwrap(),
        "-o",
        tmp.path().to_str().unwrap(),
        "-q",
        "--scale",
        "0.5",
        "--pattern-units",
        "in",
        "--page",
        "letter",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(tmp.path());
    assert!((r["pattern"]["width_mm"].as_f64().unwrap() - 120.0).abs() < 1e-9);
    assert_eq!(r["pattern"]["page"], "Letter");
    let d = ezdxf_cut(&tmp.path().join("pattern.dxf"));
    assert_eq!(d["insunits"], 1, "inches");
    assert!((d["width"].as_f64().unwrap() - 120.0 / 25.4).abs() < 1e-9, "{d}");
    let info = Command::new("pdfinfo")
        .arg(tmp.path().join("pattern.pdf"))
        .output()
        .expect("pdfinfo runs");
    assert!(
        String::from_utf8_lossy(&info.stdout).contains("612 x 792"),
        "{}",
        String::from_utf8_lossy(&info.stdout)
    );
    let bad = sheetform(&[
        "bend",
        scene.to_str().unwrap(),
        "-o",
        tmp.path().join("x").to_str().unwrap(),
        "--scale=-1",
    ]);
    assert_eq!(bad.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("scale"));
}

/// No blank pages: the desk's pattern (a 1 020 mm square sheet with a hole in the middle)
/// tiles into 5 × 6 A4 windows, and only those that show a line or a label are printed
/// (14 of 30); pdfinfo counts the pages and every one renders with red cut-line pixels.
#[test]
fn empty_tiles_are_not_printed() {
    let tmp = tempfile::tempdir().unwrap();
    let o = sheetform(&[
        "bend",
        repo().join("examples/desk.json").to_str().unwrap(),
        "-o",
        tmp.path().to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(tmp.path());
    let tiles = r["pattern"]["tile_rows"].as_u64().unwrap() * r["pattern"]["tile_columns"].as_u64().unwrap();
    let pages = r["pattern"]["page_count"].as_u64().unwrap();
    assert!(pages < tiles, "{pages} pages of {tiles} tiles");
    let info = Command::new("pdfinfo")
        .arg(tmp.path().join("pattern.pdf"))
        .output()
        .expect("pdfinfo runs");
    let text = String::from_utf8_lossy(&info.stdout);
    let counted: u64 = text
        .lines()
        .find_map(|l| l.strip_prefix("Pages:"))
        .and_then(|n| n.trim().parse().ok())
        .expect("pdfinfo prints the page count");
    assert_eq!(counted, pages, "{text}");
    // Every page shows part of the pattern: some strongly red pixel (a cut line).
    // Rendered as raw PPM (P6: a text header of magic, size and maximum, then RGB bytes).
    let render = Command::new("pdftoppm")
        .args(["-r", "20"])
        .arg(tmp.path().join("pattern.pdf"))
        .arg(tmp.path().join("page"))
        .output()
        .expect("pdftoppm runs");
    assert!(render.status.success(), "{}", String::from_utf8_lossy(&render.stderr));
    let mut rendered = 0;
    for entry in std::fs::read_dir(tmp.path()).unwrap() {
        let path = entry.unwrap().path();
        if !path.file_name().unwrap().to_string_lossy().starts_with("page") {
            continue;
        }
        rendered += 1;
        let bytes = std::fs::read(&path).unwrap();
        // Skip the three header lines.
        let mut newlines = 0;
        let start = bytes
            .iter()
            .position(|&b| {
                newlines += usize::from(b == b'\n');
                newlines == 3
            })
            .unwrap()
            + 1;
        let red = bytes[start..].chunks(3).any(|p| p[0] > 150 && p[1] < 90 && p[2] < 90);
        assert!(red, "{} shows no cut line", path.display());
    }
    assert_eq!(rendered as u64, pages);
}
