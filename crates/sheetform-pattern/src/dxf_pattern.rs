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

/// The pattern as DXF (AutoCAD R2000, so that LWPOLYLINE entities are kept), coordinates
/// in `unit` with `$INSUNITS` and `$MEASUREMENT` set accordingly and `$EXTMIN`/`$EXTMAX`
/// around the pattern. Layers: `CUT` (closed LWPOLYLINEs, glue tabs included, red),
/// `MOUNTAIN` and `VALLEY` (LINEs: mountain folds red, valley folds blue), `FOLD` (bending
/// guides and tab bases, grey), `LABEL` (TEXT: piece names and seam IDs) and `SHEET` (sheet
/// outlines, when packed). The dxf crate writes the table heads without handles (ezdxf
/// repairs 7 of them on reading; issue 23).
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
    let (lo, hi) = pattern.bounds();
    if lo.x.is_finite() && hi.x.is_finite() {
        drawing.header.minimum_drawing_extents = Point::new(lo.x * k, lo.y * k, 0.0);
        drawing.header.maximum_drawing_extents = Point::new(hi.x * k, hi.y * k, 0.0);
    }
    for (name, colour) in [
        ("CUT", 1u8),
        ("MOUNTAIN", 1),
        ("VALLEY", 5),
        ("FOLD", 8),
        ("LABEL", 5),
        ("SHEET", 7),
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
        // Mountain and valley folds on layers of their own (a cutter or plotter takes them
        // as different tools: score from the front or the back); guides and tab bases
        // stay on FOLD.
        let (layer, colour) = match f.style {
            FoldStyle::Mountain => ("MOUNTAIN", 1),
            FoldStyle::Valley => ("VALLEY", 5),
            FoldStyle::Guide | FoldStyle::TabBase => ("FOLD", 8),
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
            value: label.text.clone(),
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
    Ok(out)
}
