use crate::{FoldStyle, Pattern, PatternError, Vec2};
use dxf::entities::{Entity, EntityType, Line, LwPolyline, Text};
use dxf::enums::{AcadVersion, DrawingUnits, Units};
use dxf::tables::Layer;
use dxf::{Color, Drawing, LwPolylineVertex, Point};

/// Length unit of the DXF coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum DxfUnit {
    /// Millimetres (default).
    #[default]
    Mm,
    /// Centimetres.
    Cm,
    /// Inches.
    In,
}

impl DxfUnit {
    fn per_mm(self) -> f64 {
        match self {
            DxfUnit::Mm => 1.0,
            DxfUnit::Cm => 0.1,
            DxfUnit::In => 1.0 / 25.4,
        }
    }
}

/// The header GUID of every pattern (`$FINGERPRINTGUID`, `$VERSIONGUID`): fixed, so that
/// the file depends only on the pattern.
const PATTERN_GUID: u128 = 0x5348_4545_5446_4f52_4d00_0000_0000_0001;

/// The pattern as DXF (AutoCAD R2000, so that LWPOLYLINE entities are kept), coordinates
/// in `unit` with `$INSUNITS` and `$MEASUREMENT` set accordingly and `$EXTMIN`/`$EXTMAX`
/// around the pattern. Layers, one kind of line each so that a cutter can give each its
/// own tool: `CUT` (closed LWPOLYLINEs, glue tabs included, and notches, red),
/// `MOUNTAIN` and `VALLEY` (LINEs to score: mountain folds red, valley folds blue), `TAB`
/// (LINEs to score: the bases of the glue tabs, cyan), `GUIDE` (LINEs to draw, never to
/// score: bending guides such as the rulings of a smooth sheet, and the tangent lines of
/// bend zones, grey), `STITCH` (the stitch line inside a seam allowance, green), `GRAIN`
/// (grain lines, grey), `LABEL` (TEXT: piece names and seam IDs) and `SHEET` (sheet
/// outlines, when packed). Every table head gets a handle (the dxf crate leaves them out;
/// see `with_table_handles`), so ezdxf reads the file without repairs.
///
/// # Errors
/// The writer fails (it does not on valid input).
pub fn dxf_bytes(pattern: &Pattern, unit: DxfUnit) -> Result<Vec<u8>, PatternError> {
    let k = unit.per_mm();
    let mut drawing = Drawing::new();
    drawing.header.version = AcadVersion::R2000;
    drawing.header.default_drawing_units = match unit {
        DxfUnit::Mm => Units::Millimeters,
        DxfUnit::Cm => Units::Centimeters,
        DxfUnit::In => Units::Inches,
    };
    // $MEASUREMENT agrees with $INSUNITS, and $EXTMIN/$EXTMAX frame the pattern (CAD
    // programs zoom to them).
    drawing.header.drawing_units = match unit {
        DxfUnit::In => DrawingUnits::English,
        DxfUnit::Mm | DxfUnit::Cm => DrawingUnits::Metric,
    };
    // The same pattern gives the same bytes (a cutter's job files can be compared, a run
    // repeated): the header's dates and GUIDs, the time of writing and random numbers by
    // default, are fixed. The GUID names sheetform's patterns; the dates are 2000-01-01.
    // The writer counts local dates in days from the local 1900-01-01: a date that far
    // from that epoch is written the same in every time zone.
    let days = chrono::TimeDelta::days(36_524);
    if let Some(local) = chrono::TimeZone::with_ymd_and_hms(&chrono::Local, 1900, 1, 1, 0, 0, 0).earliest() {
        drawing.header.creation_date = local + days;
        drawing.header.update_date = local + days;
    }
    if let Some(utc) = chrono::TimeZone::with_ymd_and_hms(&chrono::Utc, 1900, 1, 1, 0, 0, 0).earliest() {
        drawing.header.creation_date_universal = utc + days;
        drawing.header.update_date_universal = utc + days;
    }
    drawing.header.fingerprint_guid = uuid::Uuid::from_u128(PATTERN_GUID);
    drawing.header.version_guid = uuid::Uuid::from_u128(PATTERN_GUID);
    let (lo, hi) = pattern.bounds();
    if lo.x.is_finite() && hi.x.is_finite() {
        drawing.header.minimum_drawing_extents = Point::new(lo.x * k, lo.y * k, 0.0);
        drawing.header.maximum_drawing_extents = Point::new(hi.x * k, hi.y * k, 0.0);
    }
    for (name, colour) in [
        ("CUT", 1u8),
        ("MOUNTAIN", 1),
        ("VALLEY", 5),
        ("TAB", 4),
        ("GUIDE", 8),
        ("LABEL", 5),
        ("SHEET", 7),
        ("STITCH", 3),
        ("GRAIN", 8),
    ] {
        drawing.add_layer(Layer {
            name: name.into(),
            color: Color::from_index(colour),
            ..Default::default()
        });
    }
    let closed = |points: &[Vec2]| {
        let mut poly = LwPolyline::default();
        poly.set_is_closed(true);
        poly.vertices = points
            .iter()
            .map(|p| LwPolylineVertex {
                x: p.x * k,
                y: p.y * k,
                ..Default::default()
            })
            .collect();
        poly
    };
    for cycle in pattern.cut_loops() {
        let mut e = Entity::new(EntityType::LwPolyline(closed(cycle)));
        e.common.layer = "CUT".into();
        drawing.add_entity(e);
    }
    for f in pattern.folds() {
        let mut e = Entity::new(EntityType::Line(Line::new(
            Point::new(f.a.x * k, f.a.y * k, 0.0),
            Point::new(f.b.x * k, f.b.y * k, 0.0),
        )));
        // Every kind of line on a layer of its own (a cutter or plotter takes them as
        // different tools: score mountains from the front, valleys from the back, tab
        // bases; draw guides, which must not be scored).
        let (layer, colour) = match f.style {
            FoldStyle::Mountain => ("MOUNTAIN", 1),
            FoldStyle::Valley => ("VALLEY", 5),
            FoldStyle::TabBase => ("TAB", 4),
            FoldStyle::Guide => ("GUIDE", 8),
            // Notches are cuts; the stitch line and the grain line are drawn, not cut.
            FoldStyle::Notch => ("CUT", 1),
            FoldStyle::Stitch => ("STITCH", 3),
            FoldStyle::Grain => ("GRAIN", 8),
        };
        e.common.layer = layer.into();
        e.common.color = Color::from_index(colour);
        drawing.add_entity(e);
    }
    for label in pattern.labels() {
        let t = Text {
            location: Point::new(label.position.x * k, label.position.y * k, 0.0),
            text_height: label.height_mm * k,
            rotation: label.angle_radians.to_degrees(),
            // A DXF group value is one line: a line break or other control character in
            // a name would end it early and shift every group after it.
            value: label
                .text
                .chars()
                .map(|c| if c.is_control() { ' ' } else { c })
                .collect(),
            ..Default::default()
        };
        let mut e = Entity::new(EntityType::Text(t));
        e.common.layer = "LABEL".into();
        drawing.add_entity(e);
    }
    for (corner, size) in &pattern.sheets {
        let rect = [
            *corner,
            corner + Vec2::new(size.x, 0.0),
            corner + size,
            corner + Vec2::new(0.0, size.y),
        ];
        let mut e = Entity::new(EntityType::LwPolyline(closed(&rect)));
        e.common.layer = "SHEET".into();
        drawing.add_entity(e);
    }
    let mut out = Vec::new();
    drawing.save(&mut out).map_err(|e| PatternError::Dxf(e.to_string()))?;
    let text = String::from_utf8(out).map_err(|e| PatternError::Dxf(e.to_string()))?;
    Ok(with_table_handles(&text).into_bytes())
}

/// The DXF text with a handle (group 5, from `$HANDSEED` on, which is moved past them)
/// and a null owner (330) on every table head: the dxf crate leaves them out, and
/// readers such as ezdxf then repair the file. A text without `$HANDSEED` is returned as
/// is.
fn with_table_handles(text: &str) -> String {
    let newline = if text.contains("\r\n") { "\r\n" } else { "\n" };
    let lines: Vec<&str> = text.lines().collect();
    let mut pairs: Vec<(String, String)> = lines
        .chunks(2)
        .filter(|c| c.len() == 2)
        .map(|c| (c[0].trim().to_string(), c[1].to_string()))
        .collect();
    let Some(seed_at) = pairs
        .iter()
        .position(|(code, value)| code == "9" && value.trim() == "$HANDSEED")
        .map(|i| i + 1)
    else {
        return text.to_string();
    };
    let Ok(mut seed) = u64::from_str_radix(pairs[seed_at].1.trim(), 16) else {
        return text.to_string();
    };
    let mut out: Vec<(String, String)> = Vec::with_capacity(pairs.len() + 32);
    let mut i = 0;
    while i < pairs.len() {
        let head = pairs[i].0 == "0" && pairs[i].1.trim() == "TABLE" && pairs.get(i + 1).is_some_and(|p| p.0 == "2");
        out.push(std::mem::take(&mut pairs[i]));
        if head {
            out.push(std::mem::take(&mut pairs[i + 1]));
            out.push(("5".into(), format!("{seed:X}")));
            out.push(("330".into(), "0".into()));
            seed += 1;
            i += 2;
        } else {
            i += 1;
        }
    }
    // $HANDSEED is in the header, before any table: its index is unchanged.
    out[seed_at].1 = format!("{seed:X}");
    let mut result = String::with_capacity(text.len() + 256);
    for (code, value) in out {
        result.push_str(&code);
        result.push_str(newline);
        result.push_str(&value);
        result.push_str(newline);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Table heads get consecutive handles from $HANDSEED, which moves past them; other
    /// pairs are untouched.
    #[test]
    fn table_heads_get_handles_from_the_seed() {
        let text = "  0\nSECTION\n  2\nHEADER\n  9\n$HANDSEED\n  5\n1F\n  0\nENDSEC\n  0\nSECTION\n  2\nTABLES\n  0\nTABLE\n  2\nLTYPE\n100\nAcDbSymbolTable\n  0\nENDTAB\n  0\nTABLE\n  2\nLAYER\n  0\nENDTAB\n  0\nENDSEC\n  0\nEOF\n";
        let fixed = with_table_handles(text);
        let lines: Vec<&str> = fixed.lines().collect();
        let after = |name: &str| {
            let at = lines.iter().position(|l| *l == name).unwrap();
            (lines[at + 1], lines[at + 2], lines[at + 3], lines[at + 4])
        };
        assert_eq!(after("LTYPE"), ("5", "1F", "330", "0"));
        assert_eq!(after("LAYER"), ("5", "20", "330", "0"));
        let seed = lines.iter().position(|l| *l == "$HANDSEED").unwrap();
        assert_eq!(lines[seed + 2], "21");
        assert!(fixed.ends_with("EOF\n"));
        // Without a seed nothing changes.
        assert_eq!(with_table_handles("  0\nEOF\n"), "  0\nEOF\n");
    }
}
