//! The flat sheet of Fig. 2: a rectangle `2 (L2 + L3)` long and `L1` wide, with
//! `N − 1` slits of width `L4` and length `2 L3` centred on its middle line, leaving `N`
//! strips between two unslit side panels of length `L2`.

use crate::{SheetSpec, SlitError};
use sheetform_geometry::{refused_number, short_number};

/// The flat sheet's dimensions, validated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SheetLayout {
    /// L1, the sheet's width.
    pub width: f64,
    /// L2, the length of each side panel.
    pub panel_length: f64,
    /// L3, the length of each half strip.
    pub strip_length: f64,
    /// L4, the slit width.
    pub slit_width: f64,
    /// N, the number of strips.
    pub strip_count: usize,
    /// M, quads per half strip.
    pub quads_per_strip: usize,
    /// Width of one strip, `(L1 − (N − 1) L4) / N`.
    pub strip_width: f64,
}

/// Largest sheet length (`l1_width`, `l2_panel_length`, `l3_strip_length`; model units:
/// a kilometre in millimetres).
pub const MAX_LENGTH: f64 = 1e6;

impl SheetLayout {
    /// Validates the sheet of a scene.
    ///
    /// # Errors
    /// A length that is not a positive number, no strips, no quads, or slits that leave
    /// no material between them, each naming the field.
    pub fn new(spec: &SheetSpec) -> Result<Self, SlitError> {
        for (name, value) in [
            ("sheet.l1_width", spec.l1_width),
            ("sheet.l2_panel_length", spec.l2_panel_length),
            ("sheet.l3_strip_length", spec.l3_strip_length),
            ("sheet.l4_slit_width", spec.l4_slit_width),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(SlitError::field(
                    name,
                    format!("must be a positive length, got {}", short_number(value)),
                ));
            }
        }
        // Lengths within six orders of magnitude of each other (1e308 made the strip
        // solver's iterations overflow and run on; 1e100 overflowed the triangulation).
        let largest = spec.l1_width.max(spec.l2_panel_length).max(spec.l3_strip_length);
        if largest > MAX_LENGTH {
            return Err(SlitError::field(
                "sheet",
                format!(
                    "lengths up to {} model units, got {}",
                    short_number(MAX_LENGTH),
                    refused_number(largest, &[MAX_LENGTH])
                ),
            ));
        }
        for (name, value) in [
            ("sheet.l1_width", spec.l1_width),
            ("sheet.l2_panel_length", spec.l2_panel_length),
            ("sheet.l3_strip_length", spec.l3_strip_length),
            ("sheet.l4_slit_width", spec.l4_slit_width),
        ] {
            if value < 1e-6 * largest {
                return Err(SlitError::field(
                    name,
                    format!(
                        "{} is less than a millionth of the sheet's largest length {}",
                        refused_number(value, &[1e-6 * largest]),
                        short_number(largest)
                    ),
                ));
            }
        }
        if spec.strip_count == 0 {
            return Err(SlitError::field("sheet.strip_count", "must be at least 1"));
        }
        if spec.quads_per_strip < 2 {
            return Err(SlitError::field(
                "sheet.quads_per_strip",
                format!("must be at least 2, got {}", spec.quads_per_strip),
            ));
        }
        if spec.quads_per_strip > crate::MAX_QUADS_SOLVED_TOGETHER {
            return Err(SlitError::field(
                "sheet.quads_per_strip",
                format!(
                    "at most {}, got {}",
                    crate::MAX_QUADS_SOLVED_TOGETHER,
                    spec.quads_per_strip
                ),
            ));
        }
        let slits = (spec.strip_count - 1) as f64 * spec.l4_slit_width;
        let strip_width = (spec.l1_width - slits) / spec.strip_count as f64;
        if strip_width <= 1e-9 * spec.l1_width {
            return Err(SlitError::field(
                "sheet.l4_slit_width",
                format!(
                    "{} slits of width {} take {} of the sheet's width l1_width = {}: no material is left for the strips",
                    spec.strip_count - 1,
                    short_number(spec.l4_slit_width),
                    short_number(slits),
                    short_number(spec.l1_width)
                ),
            ));
        }
        Ok(Self {
            width: spec.l1_width,
            panel_length: spec.l2_panel_length,
            strip_length: spec.l3_strip_length,
            slit_width: spec.l4_slit_width,
            strip_count: spec.strip_count,
            quads_per_strip: spec.quads_per_strip,
            strip_width,
        })
    }

    /// `z` (= flat `v`) of strip `k`'s left long edge.
    pub fn strip_left_edge(&self, strip: usize) -> f64 {
        strip as f64 * (self.strip_width + self.slit_width)
    }

    /// `L2 + L3`: half the sheet's length, the normaliser of the error `E` (§4).
    pub fn half_length(&self) -> f64 {
        self.panel_length + self.strip_length
    }
}
