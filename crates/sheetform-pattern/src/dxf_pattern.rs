use crate::{Pattern, PatternError};
use dxf::entities::{Entity, EntityType, Line, LwPolyline, Text};
use dxf::enums::{AcadVersion, Units};
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

/// The pattern as DXF (AutoCAD R2000, so that LWPOLYLINE entities are kept): layer `CUT`
/// (closed LWPOLYLINEs, red), `FOLD` (LINEs, grey) and `LABEL` (TEXT, blue), coordinates in
/// `unit` with `$INSUNITS` set accordingly.
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
    for (name, colour) in [("CUT", 1u8), ("FOLD", 8), ("LABEL", 5)] {
        drawing.add_layer(Layer {
            name: name.into(),
            color: Color::from_index(colour),
            ..Default::default()
        });
    }
    for cycle in &pattern.cut {
        let mut poly = LwPolyline::default();
        poly.set_is_closed(true);
        poly.vertices = cycle
            .iter()
            .map(|p| LwPolylineVertex {
                x: p.x * k,
                y: p.y * k,
                ..Default::default()
            })
            .collect();
        let mut e = Entity::new(EntityType::LwPolyline(poly));
        e.common.layer = "CUT".into();
        drawing.add_entity(e);
    }
    for [a, b] in &pattern.fold {
        let mut e = Entity::new(EntityType::Line(Line::new(
            Point::new(a.x * k, a.y * k, 0.0),
            Point::new(b.x * k, b.y * k, 0.0),
        )));
        e.common.layer = "FOLD".into();
        drawing.add_entity(e);
    }
    for (p, text) in &pattern.labels {
        let t = Text {
            location: Point::new(p.x * k, p.y * k, 0.0),
            text_height: 4.0 * k,
            value: text.clone(),
            ..Default::default()
        };
        let mut e = Entity::new(EntityType::Text(t));
        e.common.layer = "LABEL".into();
        drawing.add_entity(e);
    }
    let mut out = Vec::new();
    drawing.save(&mut out).map_err(|e| PatternError::Dxf(e.to_string()))?;
    Ok(out)
}
