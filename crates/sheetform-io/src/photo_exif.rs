//! What a photograph's EXIF says about the camera that took it (kamadak-exif).

/// The focal length in mm, 35 mm film equivalent, that the photo's EXIF records
/// (`FocalLengthIn35mmFilm`, tag 0xA405, written by phones and most cameras), or `None`
/// when the file has no EXIF, no such tag, or a zero in it (the EXIF standard's
/// "unknown"). The plain `FocalLength` (0x920A) is not used: it needs the sensor's size,
/// which few cameras record reliably.
pub fn focal_length_35mm_from_exif(bytes: &[u8]) -> Option<f64> {
    let exif = exif::Reader::new()
        .read_from_container(&mut std::io::Cursor::new(bytes))
        .ok()?;
    let field = exif.get_field(exif::Tag::FocalLengthIn35mmFilm, exif::In::PRIMARY)?;
    let value = field.value.get_uint(0)?;
    (value > 0).then_some(f64::from(value))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A JPEG with an APP1 EXIF segment holding `FocalLengthIn35mmFilm = 26` is read as
    /// 26 mm; the same without the tag, and a PNG without EXIF, as `None`.
    #[test]
    fn reads_the_35mm_focal_length_of_a_jpeg() {
        assert_eq!(focal_length_35mm_from_exif(&jpeg_with_focal(Some(26))), Some(26.0));
        assert_eq!(focal_length_35mm_from_exif(&jpeg_with_focal(Some(0))), None);
        assert_eq!(focal_length_35mm_from_exif(&jpeg_with_focal(None)), None);
        assert_eq!(focal_length_35mm_from_exif(b"\x89PNG\r\n\x1a\n"), None);
    }

    /// A minimal JPEG container: SOI, an APP1 "Exif" segment with a little-endian TIFF
    /// header, IFD0 pointing to an Exif IFD with the tag (or with none), EOI.
    fn jpeg_with_focal(focal: Option<u16>) -> Vec<u8> {
        let mut tiff: Vec<u8> = Vec::new();
        tiff.extend_from_slice(b"II*\0");
        tiff.extend_from_slice(&8u32.to_le_bytes());
        // IFD0 at 8: one entry, ExifIFDPointer (0x8769, LONG) -> 26.
        tiff.extend_from_slice(&1u16.to_le_bytes());
        tiff.extend_from_slice(&0x8769u16.to_le_bytes());
        tiff.extend_from_slice(&4u16.to_le_bytes());
        tiff.extend_from_slice(&1u32.to_le_bytes());
        tiff.extend_from_slice(&26u32.to_le_bytes());
        tiff.extend_from_slice(&0u32.to_le_bytes());
        // Exif IFD at 26.
        let entries: Vec<(u16, u16, u32, u32)> = match focal {
            Some(f) => vec![(0xA405, 3, 1, u32::from(f))],
            None => vec![(0x9000, 7, 4, u32::from_le_bytes(*b"0231"))],
        };
        tiff.extend_from_slice(&(entries.len() as u16).to_le_bytes());
        for (tag, kind, count, value) in entries {
            tiff.extend_from_slice(&tag.to_le_bytes());
            tiff.extend_from_slice(&kind.to_le_bytes());
            tiff.extend_from_slice(&count.to_le_bytes());
            tiff.extend_from_slice(&value.to_le_bytes());
        }
        tiff.extend_from_slice(&0u32.to_le_bytes());
        let mut app1 = b"Exif\0\0".to_vec();
        app1.extend_from_slice(&tiff);
        let mut out = vec![0xFF, 0xD8, 0xFF, 0xE1];
        out.extend_from_slice(&((app1.len() + 2) as u16).to_be_bytes());
        out.extend_from_slice(&app1);
        out.extend_from_slice(&[0xFF, 0xD9]);
        out
    }
}
