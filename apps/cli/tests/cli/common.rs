//! Helpers of the CLI tests: run the binary, read reports, OBJ, SVG and DXF back.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub(crate) fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .unwrap()
}

pub(crate) fn sheetform(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sheetform"))
        .args(args)
        .output()
        .expect("the binary runs")
}

pub(crate) fn report(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap()
}

/// Minimal OBJ reader: positions, texture coordinates, faces (v/vt/vn), groups.
pub(crate) struct Obj {
    pub(crate) v: Vec<[f64; 3]>,
    pub(crate) vt: Vec<[f64; 2]>,
    pub(crate) faces: Vec<[(usize, usize); 3]>,
    pub(crate) groups: Vec<String>,
}

pub(crate) fn read_obj(path: &Path) -> Obj {
    let mut o = Obj {
        v: vec![],
        vt: vec![],
        faces: vec![],
        groups: vec![],
    };
    for line in std::fs::read_to_string(path).unwrap().lines() {
        let p: Vec<&str> = line.split_whitespace().collect();
        match p.first().copied() {
            Some("v") => {
                o.v.push([p[1].parse().unwrap(), p[2].parse().unwrap(), p[3].parse().unwrap()])
            }
            Some("vt") => o.vt.push([p[1].parse().unwrap(), p[2].parse().unwrap()]),
            Some("g") => o.groups.push(p[1..].join(" ")),
            Some("f") => {
                let idx = |s: &str| {
                    let mut it = s.split('/');
                    let v: usize = it.next().unwrap().parse().unwrap();
                    let t: usize = it.next().unwrap().parse().unwrap();
                    (v - 1, t - 1)
                };
                o.faces.push([idx(p[1]), idx(p[2]), idx(p[3])]);
            }
            _ => {}
        }
    }
    o
}

/// Largest relative difference between 3D (`v`) and flat (`vt`) edge lengths.
pub(crate) fn obj_isometry_error(o: &Obj) -> f64 {
    let mut worst: f64 = 0.0;
    for f in &o.faces {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            let d3 = (0..3).map(|i| (o.v[a.0][i] - o.v[b.0][i]).powi(2)).sum::<f64>().sqrt();
            let d2 = (0..2)
                .map(|i| (o.vt[a.1][i] - o.vt[b.1][i]).powi(2))
                .sum::<f64>()
                .sqrt();
            if d2 > 0.0 {
                worst = worst.max((d3 - d2).abs() / d2);
            }
        }
    }
    worst
}

pub(crate) fn examples() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(repo().join("examples"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    v.sort();
    v
}

/// Runs the Khronos glTF validator (npm `gltf-validator`, installed by `scripts/test.sh`).
pub(crate) fn validate_glb(files: &[PathBuf]) {
    let tool = repo().join("tools/gltf-validate");
    assert!(
        tool.join("node_modules/gltf-validator").exists(),
        "the glTF validator is not installed: run `npm ci --prefix tools/gltf-validate` (scripts/test.sh does)"
    );
    let o = Command::new("node")
        .arg(tool.join("validate.js"))
        .args(files)
        .output()
        .expect("node runs");
    assert!(
        o.status.success(),
        "glTF validator found errors:\n{}",
        String::from_utf8_lossy(&o.stdout)
    );
    for line in String::from_utf8_lossy(&o.stdout).lines() {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        assert_eq!(v["errors"], 0, "{line}");
        assert_eq!(v["warnings"], 0, "{line}");
    }
}

/// A mesh bundled in `examples/meshes` (sources and licences in its SOURCES.md).
pub(crate) fn example_mesh(name: &str) -> PathBuf {
    repo().join("examples/meshes").join(name)
}

/// Cut loops of an SVG pattern (layer `cut`) as point lists (mm, SVG coordinates).
pub(crate) fn svg_cut_loops(svg: &str) -> Vec<Vec<[f64; 2]>> {
    let layer = &svg[svg.find(r#"<g id="cut""#).unwrap()..];
    let layer = &layer[..layer.find("</g>").unwrap()];
    layer
        .split("<path ")
        .skip(1)
        .map(|tag| {
            let at = if tag.starts_with(r#"d=""#) {
                0
            } else {
                tag.find(r#" d=""#).unwrap() + 1
            };
            &tag[at + 3..]
        })
        .map(|d| {
            d[..d.find('"').unwrap()]
                .split_whitespace()
                .filter(|t| t.starts_with('M') || t.starts_with('L'))
                .map(|t| {
                    let (x, y) = t[1..].split_once(',').unwrap();
                    [x.parse().unwrap(), y.parse().unwrap()]
                })
                .collect()
        })
        .collect()
}

/// Texts of one class in the SVG's label layer.
pub(crate) fn svg_texts(svg: &str, class: &str) -> Vec<String> {
    let marker = format!(r#"<text class="{class}""#);
    svg.split(&marker)
        .skip(1)
        .map(|t| t[t.find('>').unwrap() + 1..t.find("</text>").unwrap()].to_string())
        .collect()
}

/// Pairs of cut segments that meet, other than neighbours in one loop at their shared
/// point.
pub(crate) fn cut_intersections(loops: &[Vec<[f64; 2]>]) -> usize {
    let mut segments = Vec::new();
    for (l, points) in loops.iter().enumerate() {
        for i in 0..points.len() {
            segments.push((l, i, points.len(), points[i], points[(i + 1) % points.len()]));
        }
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let mut hits = 0;
    for (x, &(la, ia, na, a0, a1)) in segments.iter().enumerate() {
        for &(lb, ib, _, b0, b1) in &segments[x + 1..] {
            if la == lb && (ib == (ia + 1) % na || ia == (ib + 1) % na) {
                continue;
            }
            let (d1, d2) = (cross(a0, a1, b0), cross(a0, a1, b1));
            let (d3, d4) = (cross(b0, b1, a0), cross(b0, b1, a1));
            if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
                hits += 1;
            }
        }
    }
    hits
}

/// CUT layer of a DXF as read by ezdxf (an independent reader): audit error count,
/// polyline count, total signed area and bounds.
pub(crate) fn ezdxf_cut(path: &Path) -> serde_json::Value {
    let script = r#"
import ezdxf, json, sys
doc = ezdxf.readfile(sys.argv[1])
auditor = doc.audit()
polys = [e for e in doc.modelspace().query('LWPOLYLINE') if e.dxf.layer == 'CUT']
area, xs, ys = 0.0, [], []
for p in polys:
    pts = [(x, y) for x, y, *_ in p.get_points()]
    area += 0.5 * sum(a[0] * b[1] - b[0] * a[1] for a, b in zip(pts, pts[1:] + pts[:1]))
    xs += [x for x, _ in pts]; ys += [y for _, y in pts]
print(json.dumps({"errors": len(auditor.errors), "closed": all(p.closed for p in polys), "count": len(polys),
  "area": area, "width": max(xs) - min(xs), "height": max(ys) - min(ys),
  "layers": sorted(l.dxf.name for l in doc.layers), "insunits": doc.header.get('$INSUNITS', 0),
  "folds": len([e for e in doc.modelspace().query('LINE') if e.dxf.layer in ('GUIDE', 'TAB', 'MOUNTAIN', 'VALLEY')]),
  "mountain": len([e for e in doc.modelspace().query('LINE') if e.dxf.layer == 'MOUNTAIN']),
  "valley": len([e for e in doc.modelspace().query('LINE') if e.dxf.layer == 'VALLEY']),
  "fixes": len(auditor.fixes), "measurement": doc.header.get('$MEASUREMENT', 0),
  "extmin": list(doc.header.get('$EXTMIN', (0, 0, 0)))[:2], "extmax": list(doc.header.get('$EXTMAX', (0, 0, 0)))[:2]}))
"#;
    let o = Command::new("python3")
        .arg("-c")
        .arg(script)
        .arg(path)
        .output()
        .expect("python3 runs");
    assert!(
        o.status.success(),
        "ezdxf could not read {}: {}",
        path.display(),
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).unwrap()
}

/// Labels of an SVG pattern whose text box (0.55 em per character wide, 0.7 em high:
/// the glyphs' extent, a little inside the box the placement keeps free) meets a cut or
/// fold line or another label's box, or leaves every cut loop. Read from the file as a
/// viewer draws it (position, font size, rotation).
pub(crate) fn svg_labels_over_lines(svg: &str) -> usize {
    let attr = |tag: &str, name: &str| -> f64 {
        let key = format!(r#" {name}=""#);
        let start = tag.find(&key).unwrap() + key.len();
        tag[start..start + tag[start..].find('"').unwrap()].parse().unwrap()
    };
    let mut segments: Vec<([f64; 2], [f64; 2])> = Vec::new();
    let loops = svg_cut_loops(svg);
    for l in &loops {
        for i in 0..l.len() {
            segments.push((l[i], l[(i + 1) % l.len()]));
        }
    }
    for line in svg.split("<line ").skip(1) {
        let tag = format!(" {}", &line[..line.find("/>").unwrap()]);
        let tag = tag.as_str();
        segments.push(([attr(tag, "x1"), attr(tag, "y1")], [attr(tag, "x2"), attr(tag, "y2")]));
    }
    // Each label as (centre, direction, half width, half height).
    let boxes: Vec<([f64; 2], [f64; 2], f64, f64)> = svg
        .split("<text ")
        .skip(1)
        .map(|t| {
            let tag = &t[..t.find('>').unwrap()];
            let text = &t[t.find('>').unwrap() + 1..t.find("</text>").unwrap()];
            let (x, y, size) = (attr(tag, "x"), attr(tag, "y"), attr(tag, "font-size"));
            let rotate = tag.find("rotate(").map_or(0.0, |i| {
                tag[i + 7..].split_whitespace().next().unwrap().parse::<f64>().unwrap()
            });
            let (s, c) = rotate.to_radians().sin_cos();
            (
                [x, y],
                [c, s],
                0.5 * 0.55 * size * text.chars().count() as f64,
                0.35 * size,
            )
        })
        .collect();
    let local = |b: &([f64; 2], [f64; 2], f64, f64), p: [f64; 2]| {
        let d = [p[0] - b.0[0], p[1] - b.0[1]];
        [d[0] * b.1[0] + d[1] * b.1[1], -d[0] * b.1[1] + d[1] * b.1[0]]
    };
    let corners = |b: &([f64; 2], [f64; 2], f64, f64)| {
        [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(u, v)| {
            [
                b.0[0] + u * b.2 * b.1[0] - v * b.3 * b.1[1],
                b.0[1] + u * b.2 * b.1[1] + v * b.3 * b.1[0],
            ]
        })
    };
    // A segment meets a box when clipping it to the box leaves something.
    let meets = |b: &([f64; 2], [f64; 2], f64, f64), p: [f64; 2], q: [f64; 2]| {
        let (p, q) = (local(b, p), local(b, q));
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for axis in 0..2 {
            let half = if axis == 0 { b.2 } else { b.3 };
            let d = q[axis] - p[axis];
            for (num, den) in [(half - p[axis], d), (half + p[axis], -d)] {
                if den == 0.0 {
                    if num < 0.0 {
                        return false;
                    }
                } else if den > 0.0 {
                    t1 = t1.min(num / den);
                } else {
                    t0 = t0.max(num / den);
                }
            }
        }
        t0 <= t1
    };
    let inside = |p: [f64; 2]| {
        let mut crossings = 0;
        for l in &loops {
            for i in 0..l.len() {
                let (a, b) = (l[i], l[(i + 1) % l.len()]);
                if (a[1] > p[1]) != (b[1] > p[1]) && p[0] < a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]) {
                    crossings += 1;
                }
            }
        }
        crossings % 2 == 1
    };
    let mut bad = 0;
    for (i, b) in boxes.iter().enumerate() {
        let c = corners(b);
        let over_line = segments.iter().any(|&(p, q)| meets(b, p, q));
        let outside = !c.iter().all(|&p| inside(p));
        let over_label = boxes[..i].iter().any(|o| {
            let oc = corners(o);
            (0..4).any(|k| meets(o, c[k], c[(k + 1) % 4])) || oc.iter().any(|&p| meets(b, p, p))
        });
        if over_line || outside || over_label {
            bad += 1;
        }
    }
    bad
}

/// [`sheetform`], killed after `limit_seconds` with a panic: the guard that turns a
/// hang into a test failure (a limit far above the run's time, not a timing test).
pub(crate) fn sheetform_within(args: &[&str], limit_seconds: u64) -> Output {
    use std::io::Read;
    let mut child = Command::new(env!("CARGO_BIN_EXE_sheetform"))
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let start = std::time::Instant::now();
    // Drain the pipes on threads so a chatty child cannot block on a full pipe.
    let mut out = child.stdout.take().unwrap();
    let mut err = child.stderr.take().unwrap();
    let out = std::thread::spawn(move || {
        let mut b = Vec::new();
        out.read_to_end(&mut b).ok();
        b
    });
    let err = std::thread::spawn(move || {
        let mut b = Vec::new();
        err.read_to_end(&mut b).ok();
        b
    });
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed().as_secs() >= limit_seconds {
            child.kill().ok();
            child.wait().ok();
            panic!("sheetform {args:?} did not finish within {limit_seconds} s (a hang)");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    Output {
        status,
        stdout: out.join().unwrap(),
        stderr: err.join().unwrap(),
    }
}

/// The pattern of an output directory as a maker gets it, audited from the files
/// (`tools/pattern_audit.py`: model.obj, pattern.svg, pattern.dxf read back on their own,
/// each piece registered onto the printed outline): glued edge pairs and their tabs, seam
/// IDs on each copy, tab depths and clearances, crossings, labels, DXF layers.
pub(crate) fn pattern_audit(dir: &Path) -> serde_json::Value {
    let o = Command::new("python3")
        .arg(repo().join("tools/pattern_audit.py"))
        .arg(dir)
        .output()
        .expect("python3 runs");
    assert!(
        o.status.success(),
        "the audit could not read {}: {}",
        dir.display(),
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).unwrap()
}

/// An OBJ of the height field `z = height(x, y)` over a 100 mm square centred on the origin
/// (`x, y` in [−0.5, 0.5]), `n × n` cells, two triangles each.
pub(crate) fn grid_obj(n: usize, height: impl Fn(f64, f64) -> f64) -> String {
    grid_obj_in_groups(n, height, |_, _| None)
}

/// As [`grid_obj`], the two faces of cell `(i, j)` (`x` from `i / n − 0.5` to `(i + 1) / n −
/// 0.5`, `y` likewise with `j`) in the OBJ group `group(i, j)` (none: before any `g` line).
pub(crate) fn grid_obj_in_groups(
    n: usize,
    height: impl Fn(f64, f64) -> f64,
    group: impl Fn(usize, usize) -> Option<&'static str>,
) -> String {
    let mut obj = String::new();
    for i in 0..=n {
        for j in 0..=n {
            let (x, y) = (i as f64 / n as f64 - 0.5, j as f64 / n as f64 - 0.5);
            obj += &format!("v {} {} {}\n", 100.0 * x, 100.0 * y, height(x, y));
        }
    }
    let id = |i: usize, j: usize| i * (n + 1) + j + 1;
    // Faces by group, the groups in the order they first appear.
    let mut groups: Vec<(Option<&str>, String)> = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let name = group(i, j);
            let at = match groups.iter().position(|(g, _)| *g == name) {
                Some(at) => at,
                None => {
                    groups.push((name, String::new()));
                    groups.len() - 1
                }
            };
            groups[at].1 += &format!(
                "f {} {} {}\nf {} {} {}\n",
                id(i, j),
                id(i + 1, j),
                id(i + 1, j + 1),
                id(i, j),
                id(i + 1, j + 1),
                id(i, j + 1)
            );
        }
    }
    // Ungrouped faces first: a `g` line names every face after it.
    groups.sort_by_key(|(name, _)| name.is_some());
    for (name, faces) in groups {
        if let Some(name) = name {
            obj += &format!("g {name}\n");
        }
        obj += &faces;
    }
    obj
}

/// `mesh` as an OBJ file (positions, faces, the seams as `l` lines) in `dir`.
pub(crate) fn write_obj(dir: &Path, name: &str, mesh: &sheetform::mesh::TriangleMesh) -> PathBuf {
    let mut text = String::new();
    for p in &mesh.positions {
        text += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    for t in &mesh.triangles {
        text += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    for [a, b] in &mesh.seam_edges {
        text += &format!("l {} {}\n", a + 1, b + 1);
    }
    let path = dir.join(format!("{name}.obj"));
    std::fs::write(&path, text).unwrap();
    path
}
