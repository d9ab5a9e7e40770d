use serde::{Deserialize, Serialize};

/// The length unit of a model. Flat and 3D coordinates share it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum LengthUnit {
    /// Millimetres (the default).
    #[default]
    Mm,
    /// Centimetres.
    Cm,
    /// Metres.
    M,
    /// Inches (25.4 mm).
    In,
}

impl LengthUnit {
    /// Millimetres per unit.
    pub fn millimetres(self) -> f64 {
        match self {
            LengthUnit::Mm => 1.0,
            LengthUnit::Cm => 10.0,
            LengthUnit::M => 1000.0,
            LengthUnit::In => 25.4,
        }
    }

    /// The unit's symbol ("mm", "cm", "m", "in").
    pub fn symbol(self) -> &'static str {
        match self {
            LengthUnit::Mm => "mm",
            LengthUnit::Cm => "cm",
            LengthUnit::M => "m",
            LengthUnit::In => "in",
        }
    }
}

/// Which axis of a model points up. glTF's is `+Y` (and most mesh viewers read OBJ that
/// way); sheets bent by sheetform and FFD panels are built `+Z`-up. Exports turn a `+Z`-up
/// model to `+Y` up (`(x, y, z) ↦ (x, z, −y)`) so it stands upright everywhere.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum UpAxis {
    /// `+Y` up (glTF's own; photos, slit sheets, most mesh files).
    #[default]
    Y,
    /// `+Z` up (CAD, bent sheets, FFD panels).
    Z,
}

impl UpAxis {
    /// A point of the model in `+Y`-up coordinates.
    pub fn to_y_up(self, p: nalgebra::Vector3<f64>) -> nalgebra::Vector3<f64> {
        match self {
            UpAxis::Y => p,
            UpAxis::Z => nalgebra::Vector3::new(p.x, p.z, -p.y),
        }
    }
}
