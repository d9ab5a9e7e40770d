//! Pattern outputs read back by outside tools: DXF (ezdxf), PDF (pdftoppm), scales, units, sheets.

use crate::common::{cut_intersections, example_mesh, ezdxf_cut, repo, report, sheetform, svg_cut_loops};
use std::process::Command;

#[test]
fn a_piece_larger_than_the_sheet_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = sheetform(&[
        "flatten",
        example_mesh("crumpled-developable.obj").to_str().unwrap(),
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
    for layer in ["CUT", "GUIDE", "LABEL"] {
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

/// Material allowances: a seam allowance keeps every point of the design outline (the
/// stitch line) exactly the allowance inside the cut line, with notches across it and a
/// grain line per piece, in the SVG and in the DXF's layers; a kerf grows the cut by half
/// its width on every side; a seam allowance and glue tabs together are refused.
#[test]
fn seam_allowance_notches_grain_and_kerf_are_where_they_belong() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("skirt");
    let scene = repo().join("examples/ffd/skirt.json");
    let o = sheetform(&[
        "ffd",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
        "--seam-allowance",
        "10",
        "--grain-lines",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(&out);
    let p = &r["pattern"];
    let pieces = p["piece_count"].as_u64().unwrap();
    assert_eq!(p["seam_allowance_mm"], 10.0);
    assert_eq!(p["grain_line_count"].as_u64().unwrap(), pieces);
    assert!(p["notch_count"].as_u64().unwrap() >= 3 * p["seam_count"].as_u64().unwrap());
    let svg = std::fs::read_to_string(out.join("pattern.svg")).unwrap();
    let loops = svg_cut_loops(&svg);
    assert_eq!(loops.len() as u64, pieces);
    assert_eq!(cut_intersections(&loops), 0);
    // Every stitch-line point is 10 mm from the nearest cut line (mitred corners only
    // further), and inside it.
    let layer = &svg[svg.find(r#"<g id="stitch""#).unwrap()..];
    let layer = &layer[..layer.find("</g>").unwrap()];
    let number = |tag: &str, key: &str| -> f64 {
        let start = tag.find(&format!(" {key}=\"")).unwrap() + key.len() + 3;
        tag[start..start + tag[start..].find('"').unwrap()].parse().unwrap()
    };
    let mut checked = 0;
    for line in layer.split("<line").skip(1) {
        let p = [number(line, "x1"), number(line, "y1")];
        let distance = loops
            .iter()
            .flat_map(|l| (0..l.len()).map(move |i| (l[i], l[(i + 1) % l.len()])))
            .map(|(a, b)| {
                let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                let t = (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
                ((a[0] + t * dx - p[0]).powi(2) + (a[1] + t * dy - p[1]).powi(2)).sqrt()
            })
            .fold(f64::INFINITY, f64::min);
        assert!(distance >= 10.0 - 1e-3, "a stitch point {distance} mm from the cut");
        checked += 1;
    }
    assert!(checked > 100);
    let dxf = ezdxf_cut(&out.join("pattern.dxf"));
    assert_eq!(dxf["errors"], 0);
    for layer in ["STITCH", "GRAIN"] {
        assert!(dxf["layers"].as_array().unwrap().iter().any(|l| l == layer), "{dxf}");
    }

    // Kerf: the bent rectangle's cut grows by 0.2 mm on every side.
    let scene = repo().join("examples/bent-rectangle.json");
    let size = |extra: &[&str]| {
        let out = tmp.path().join("kerf");
        let mut args = vec!["bend", scene.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"];
        args.extend_from_slice(extra);
        let o = sheetform(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let d = ezdxf_cut(&out.join("pattern.dxf"));
        (d["width"].as_f64().unwrap(), d["height"].as_f64().unwrap())
    };
    let (w0, h0) = size(&[]);
    let (w, h) = size(&["--kerf", "0.4"]);
    assert!(
        (w - w0 - 0.4).abs() < 1e-4 && (h - h0 - 0.4).abs() < 1e-4,
        "{w0} × {h0} → {w} × {h}"
    );
    let out = tmp.path().join("kerf");
    assert_eq!(report(&out)["pattern"]["kerf_mm"], 0.4);

    // Tabs and a seam allowance both: refused, nothing written.
    let out = tmp.path().join("both");
    let o = sheetform(&[
        "bend",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--seam-allowance",
        "5",
        "--tabs",
        "one",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("seam_allowance_mm"));
    assert!(!out.exists());
}

/// The same scene gives the same pattern files, byte for byte, whenever and wherever it
/// runs: the DXF header's dates and GUIDs (the time of writing and random numbers by
/// default) are fixed, the same in every time zone.
#[test]
fn the_pattern_files_are_the_same_bytes_in_every_time_zone() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = repo().join("examples/bent-rectangle.json");
    let run = |tz: &str| {
        let out = tmp.path().join(tz.replace('/', "-"));
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_sheetform"))
            .args(["bend", scene.to_str().unwrap(), "-o", out.to_str().unwrap(), "--quiet"])
            .env("TZ", tz)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        ["pattern.dxf", "pattern.pdf", "pattern.svg"].map(|name| std::fs::read(out.join(name)).unwrap())
    };
    let utc = run("UTC");
    std::thread::sleep(std::time::Duration::from_millis(1100));
    for tz in ["Australia/Sydney", "America/New_York", "Asia/Kolkata"] {
        let other = run(tz);
        for (k, name) in ["pattern.dxf", "pattern.pdf", "pattern.svg"].iter().enumerate() {
            assert!(other[k] == utc[k], "{name} differs between UTC and {tz}");
        }
    }
}
