//! Image files a scene names (a bend scene's texture, a photo annotation's photograph),
//! checked by decoding them whole before anything is made from them: a file that only
//! starts like a PNG (its signature, then garbage) or that was cut off is refused with
//! what is wrong, instead of being embedded as it is in the GLB and the overlay.

use crate::Texture;
use std::io::Cursor;
use thiserror::Error;

/// Most bytes the check of a JPEG may decode into (its pixels at 8 bits per channel,
/// decoded whole: about a 350-megapixel colour photo). A PNG is checked row by row in
/// memory that does not grow with the image.
pub const MAX_DECODED_JPEG_BYTES: u64 = 1 << 30;

/// Why an image file cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ImageError {
    /// The bytes start like neither a PNG nor a JPEG.
    #[error("not a PNG or JPEG image")]
    NotAnImage,
    /// The file ends before the image does.
    #[error("the {format} file is cut off: it ends before its image data do (a truncated download or copy?)")]
    Truncated {
        /// `PNG` or `JPEG`.
        format: &'static str,
    },
    /// The image data are damaged or not what the format says.
    #[error("the {format} file is damaged: {reason}")]
    Corrupt {
        /// `PNG` or `JPEG`.
        format: &'static str,
        /// What the decoder found.
        reason: String,
    },
    /// Decoding the JPEG would take more memory than [`MAX_DECODED_JPEG_BYTES`].
    #[error(
        "the JPEG is {width} × {height} pixels, too large to check (at most {} MB decoded); scale it down",
        MAX_DECODED_JPEG_BYTES >> 20
    )]
    TooLarge {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
}

impl<'a> Texture<'a> {
    /// Recognises a PNG or JPEG by its signature and decodes it whole to check it (a
    /// PNG's every chunk with its checksum and every row of its compressed data, to its
    /// end; a JPEG's every scan), returning the image and its size in pixels (width,
    /// height) as the decoder read them.
    ///
    /// # Errors
    /// [`ImageError`]: not a PNG or JPEG, cut off, damaged, or (a JPEG) too large to
    /// decode.
    pub fn decoded(bytes: &'a [u8]) -> Result<(Self, (u32, u32)), ImageError> {
        let texture = Self::from_bytes(bytes).ok_or(ImageError::NotAnImage)?;
        let size = if texture.mime_type == "image/png" {
            check_png(bytes)?
        } else {
            check_jpeg(bytes)?
        };
        Ok((texture, size))
    }
}

fn png_error(error: png::DecodingError) -> ImageError {
    // The decoder's own text names its types (`ChunkType { type: xxxx, .. }`): kept for
    // the logs, said in words.
    tracing::debug!("PNG check: {error}");
    let reason = match error {
        png::DecodingError::IoError(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => {
            return ImageError::Truncated { format: "PNG" };
        }
        png::DecodingError::Format(e) => {
            let text = e.to_string();
            if text.starts_with("CRC error") {
                "a chunk's checksum does not match its data"
            } else if text.contains("deflate") || text.contains("zlib") {
                "its compressed image data do not decompress"
            } else {
                "its chunks are not those of a PNG image (out of order, missing or malformed)"
            }
        }
        png::DecodingError::LimitsExceeded => "it asks for more memory than a PNG row may take",
        _ => "it cannot be read as a PNG image",
    };
    ImageError::Corrupt {
        format: "PNG",
        reason: reason.to_string(),
    }
}

/// Decodes every row of a PNG, then reads on to its end chunk.
fn check_png(bytes: &[u8]) -> Result<(u32, u32), ImageError> {
    let mut decoder = png::Decoder::new(Cursor::new(bytes));
    decoder.ignore_checksums(false);
    let mut reader = decoder.read_info().map_err(png_error)?;
    let size = (reader.info().width, reader.info().height);
    while reader.next_row().map_err(png_error)?.is_some() {}
    reader.finish().map_err(png_error)?;
    Ok(size)
}

/// Decodes a JPEG whole (the decoder has no row-by-row mode), within
/// [`MAX_DECODED_JPEG_BYTES`].
fn check_jpeg(bytes: &[u8]) -> Result<(u32, u32), ImageError> {
    let corrupt = |e: image::ImageError| {
        let text = e.to_string();
        tracing::debug!("JPEG check: {text}");
        if text.contains("end of file") || text.contains("EOF") || text.contains("No more bytes") {
            ImageError::Truncated { format: "JPEG" }
        } else {
            ImageError::Corrupt {
                format: "JPEG",
                reason: "its image data cannot be decoded".to_string(),
            }
        }
    };
    let reader = || image::ImageReader::with_format(Cursor::new(bytes), image::ImageFormat::Jpeg);
    let (width, height) = reader().into_dimensions().map_err(corrupt)?;
    if u64::from(width) * u64::from(height) * 4 > MAX_DECODED_JPEG_BYTES {
        return Err(ImageError::TooLarge { width, height });
    }
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(MAX_DECODED_JPEG_BYTES);
    let mut reader = reader();
    reader.limits(limits);
    let image = reader.decode().map_err(corrupt)?;
    // The decoder fills a scan cut short near its end with grey and says nothing; a JPEG
    // ends its last scan with the end-of-image marker (FF D9; inside the entropy-coded
    // data every FF is followed by 00 or a restart marker), which a cut file lacks.
    // Bytes after it (a camera's trailer) are kept.
    let last_scan = bytes.windows(2).rposition(|w| w == [0xFF, 0xDA]);
    let ended = last_scan.is_some_and(|at| bytes[at..].windows(2).any(|w| w == [0xFF, 0xD9]));
    if !ended {
        return Err(ImageError::Truncated { format: "JPEG" });
    }
    Ok((image.width(), image.height()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(width: u32, height: u32) -> Vec<u8> {
        let mut out = Vec::new();
        image::DynamicImage::new_rgb8(width, height)
            .write_to(&mut Cursor::new(&mut out), image::ImageFormat::Png)
            .unwrap();
        out
    }

    fn jpeg(width: u32, height: u32) -> Vec<u8> {
        let mut out = Vec::new();
        let pixels = image::RgbImage::from_fn(width, height, |x, y| image::Rgb([(x * 7) as u8, (y * 5) as u8, 90]));
        image::DynamicImage::ImageRgb8(pixels)
            .write_to(&mut Cursor::new(&mut out), image::ImageFormat::Jpeg)
            .unwrap();
        out
    }

    /// Issue 35: a PNG signature followed by garbage, or a PNG cut off, was embedded in
    /// the outputs with status ok. Every image that does not decode to its end is refused
    /// with what is wrong.
    #[test]
    fn images_that_do_not_decode_are_refused() {
        let good = png(40, 30);
        let (texture, size) = Texture::decoded(&good).unwrap();
        assert_eq!((texture.mime_type, size), ("image/png", (40, 30)));
        let garbage = [&good[..8], &b"garbage garbage garbage garbage"[..]].concat();
        assert!(matches!(
            Texture::decoded(&garbage),
            Err(ImageError::Corrupt { .. } | ImageError::Truncated { .. })
        ));
        // Cut anywhere: in the header, the image data or before the end chunk.
        for cut in [20, 40, good.len() / 2, good.len() - 12, good.len() - 1] {
            let e = Texture::decoded(&good[..cut]).unwrap_err();
            assert!(
                matches!(e, ImageError::Truncated { .. } | ImageError::Corrupt { .. }),
                "{cut}: {e}"
            );
        }
        assert_eq!(
            Texture::decoded(&good[..8]).unwrap_err(),
            ImageError::Truncated { format: "PNG" }
        );
        // A flipped bit in the header's checksum, in the compressed image data.
        let mut flipped = good.clone();
        flipped[29] ^= 0x10;
        let e = Texture::decoded(&flipped).unwrap_err();
        assert!(e.to_string().contains("checksum"), "{e}");
        let mut flipped = good.clone();
        let idat = flipped.windows(4).position(|w| w == b"IDAT").unwrap();
        flipped[idat + 6] ^= 0x10;
        let e = Texture::decoded(&flipped).unwrap_err();
        assert!(e.to_string().contains("damaged"), "{e}");
        assert_eq!(Texture::decoded(b"GIF89a").unwrap_err(), ImageError::NotAnImage);
        let good = jpeg(64, 48);
        assert_eq!(Texture::decoded(&good).unwrap().1, (64, 48));
        for cut in [3, 30, good.len() / 3] {
            assert!(Texture::decoded(&good[..cut]).is_err(), "JPEG cut at {cut}");
        }
        // Cut near its end (the decoder alone accepted these, filling the rest with grey).
        for missing in [1, 2, 8] {
            assert_eq!(
                Texture::decoded(&good[..good.len() - missing]).unwrap_err(),
                ImageError::Truncated { format: "JPEG" },
                "{missing} bytes missing"
            );
        }
        // A trailer after the end-of-image marker is kept.
        let mut trailer = good.clone();
        trailer.extend_from_slice(b"camera trailer");
        assert_eq!(Texture::decoded(&trailer).unwrap().1, (64, 48));
    }
}
