//! A solve's reply with its large arrays in binary: a small JSON header and the arrays'
//! bytes as they lie in memory, for the editor to view as typed arrays instead of
//! formatting and parsing a number per value (issue 38: a 1 000-ruling bend's reply was
//! ~350 KB of JSON, most of the time of a drag).
//!
//! Asked for with `Accept: application/vnd.sheetform.arrays`; without it a route replies
//! in JSON as before (curl, scripts, the fuzz targets). The body is
//!
//! ```text
//! "SFA1"  u32 LE: header length H  header: H bytes of UTF-8 JSON  zero padding to 8
//! data: each array little-endian, starting at a multiple of 8
//! ```
//!
//! The header is the JSON reply with each array taken out left empty, plus
//! `binary_arrays`: `[{"path": "model.positions", "type": "f64", "offset": …,
//! "length": …}, …]`, offsets in bytes from the start of the data. Type `f64` and `u32`
//! are one array; `u32_lists` (rulings as vertex polylines) is `length + 1` offsets
//! followed by the indices, list `k` being `indices[offsets[k]..offsets[k + 1]]`.

use axum::http::{header, HeaderMap, HeaderValue};
use axum::response::{IntoResponse, Response};
use serde::Serialize;

/// The media type of a reply with binary arrays.
pub(crate) const ARRAYS_MEDIA_TYPE: &str = "application/vnd.sheetform.arrays";

/// One array taken out of a reply.
#[derive(Debug)]
pub(crate) enum ArrayData {
    /// Values of type `f64`.
    F64(Vec<f64>),
    /// Values of type `u32`.
    U32(Vec<u32>),
    /// Lists of `u32` (as `length + 1` offsets, then the values).
    U32Lists(Vec<Vec<u32>>),
}

/// Arrays taken out of a reply, each with its path in the JSON reply (`.` between keys).
pub(crate) type TakenArrays = Vec<(&'static str, ArrayData)>;

/// Whether the request asks for binary arrays.
pub(crate) fn wants_arrays(headers: &HeaderMap) -> bool {
    headers
        .get_all(header::ACCEPT)
        .iter()
        .filter_map(|value| value.to_str().ok())
        .flat_map(|value| value.split(','))
        .any(|media| {
            let mut parts = media.split(';');
            let named = parts.next().is_some_and(|m| m.trim() == ARRAYS_MEDIA_TYPE);
            // `q=0`: not acceptable (RFC 9110, §12.4.2).
            let refused = parts.any(|p| {
                p.trim()
                    .strip_prefix("q=")
                    .and_then(|q| q.trim().parse::<f64>().ok())
                    .is_some_and(|q| q <= 0.0)
            });
            named && !refused
        })
}

#[derive(Serialize)]
struct ArrayEntry {
    path: &'static str,
    #[serde(rename = "type")]
    kind: &'static str,
    offset: usize,
    length: usize,
}

#[derive(Serialize)]
struct WithArrays<'a, T: Serialize> {
    #[serde(flatten)]
    reply: &'a T,
    binary_arrays: Vec<ArrayEntry>,
}

fn align8(n: usize) -> usize {
    n.div_ceil(8) * 8
}

/// The body of a reply with binary arrays: `reply` (its arrays already taken out) as the
/// header, then `arrays`.
pub(crate) fn array_body<T: Serialize>(reply: &T, arrays: &TakenArrays) -> Vec<u8> {
    let mut entries = Vec::with_capacity(arrays.len());
    let mut offset = 0;
    for (path, data) in arrays {
        let (kind, length, bytes) = match data {
            ArrayData::F64(values) => ("f64", values.len(), 8 * values.len()),
            ArrayData::U32(values) => ("u32", values.len(), 4 * values.len()),
            ArrayData::U32Lists(lists) => {
                let values: usize = lists.iter().map(Vec::len).sum();
                ("u32_lists", lists.len(), 4 * (lists.len() + 1 + values))
            }
        };
        entries.push(ArrayEntry {
            path,
            kind,
            offset,
            length,
        });
        offset = align8(offset + bytes);
    }
    let header = serde_json::to_vec(&WithArrays {
        reply,
        binary_arrays: entries,
    })
    .expect("a reply serialises");
    let start = align8(8 + header.len());
    let mut body = Vec::with_capacity(start + offset);
    body.extend_from_slice(b"SFA1");
    body.extend_from_slice(&(header.len() as u32).to_le_bytes());
    body.extend_from_slice(&header);
    body.resize(start, 0);
    for (_, data) in arrays {
        match data {
            ArrayData::F64(values) => values.iter().for_each(|v| body.extend_from_slice(&v.to_le_bytes())),
            ArrayData::U32(values) => values.iter().for_each(|v| body.extend_from_slice(&v.to_le_bytes())),
            ArrayData::U32Lists(lists) => {
                let mut at = 0u32;
                body.extend_from_slice(&at.to_le_bytes());
                for list in lists {
                    at += list.len() as u32;
                    body.extend_from_slice(&at.to_le_bytes());
                }
                for value in lists.iter().flatten() {
                    body.extend_from_slice(&value.to_le_bytes());
                }
            }
        }
        body.resize(align8(body.len()), 0);
    }
    body
}

/// `reply` as JSON, or, when `headers` ask for it, with the arrays `take` takes out of it
/// in binary.
pub(crate) fn reply_with_arrays<T: Serialize>(
    headers: &HeaderMap,
    mut reply: T,
    take: impl FnOnce(&mut T) -> TakenArrays,
) -> Response {
    if !wants_arrays(headers) {
        return axum::Json(reply).into_response();
    }
    let arrays = take(&mut reply);
    (
        [(header::CONTENT_TYPE, HeaderValue::from_static(ARRAYS_MEDIA_TYPE))],
        array_body(&reply, &arrays),
    )
        .into_response()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Reads a body back as the editor does: the header, and each array at its offset.
    pub(crate) fn read_body(body: &[u8]) -> (serde_json::Value, Vec<(String, Vec<f64>)>) {
        assert_eq!(&body[..4], b"SFA1");
        let length = u32::from_le_bytes(body[4..8].try_into().unwrap()) as usize;
        let header: serde_json::Value = serde_json::from_slice(&body[8..8 + length]).unwrap();
        let start = align8(8 + length);
        let mut arrays = Vec::new();
        for entry in header["binary_arrays"].as_array().unwrap() {
            let offset = start + entry["offset"].as_u64().unwrap() as usize;
            assert_eq!(offset % 8, 0, "arrays start at multiples of 8");
            let n = entry["length"].as_u64().unwrap() as usize;
            let word = |k: usize, size: usize| &body[offset + size * k..offset + size * (k + 1)];
            let values: Vec<f64> = match entry["type"].as_str().unwrap() {
                "f64" => (0..n)
                    .map(|k| f64::from_le_bytes(word(k, 8).try_into().unwrap()))
                    .collect(),
                "u32" => (0..n)
                    .map(|k| f64::from(u32::from_le_bytes(word(k, 4).try_into().unwrap())))
                    .collect(),
                // Offsets then values, flattened.
                _ => {
                    let end = u32::from_le_bytes(word(n, 4).try_into().unwrap()) as usize;
                    (0..n + 1 + end)
                        .map(|k| f64::from(u32::from_le_bytes(word(k, 4).try_into().unwrap())))
                        .collect()
                }
            };
            arrays.push((entry["path"].as_str().unwrap().to_string(), values));
        }
        (header, arrays)
    }

    #[derive(Serialize)]
    struct Reply {
        name: String,
        values: Vec<f64>,
        lists: Vec<Vec<u32>>,
        ids: Vec<u32>,
    }

    #[test]
    fn arrays_come_back_exactly_at_aligned_offsets_and_the_rest_as_json() {
        let reply = Reply {
            name: "a\"b".into(),
            values: vec![0.1, -2.5e-300, f64::MAX, 1.0 / 3.0],
            lists: vec![vec![1, 2, 3], vec![], vec![7]],
            ids: vec![5, 4, 3],
        };
        let mut headers = HeaderMap::new();
        headers.insert(header::ACCEPT, HeaderValue::from_static("application/json"));
        assert!(!wants_arrays(&headers));
        headers.insert(
            header::ACCEPT,
            HeaderValue::from_static("application/vnd.sheetform.arrays; q=1, application/json"),
        );
        assert!(wants_arrays(&headers));
        headers.insert(
            header::ACCEPT,
            HeaderValue::from_static("application/json, application/vnd.sheetform.arrays;q=0"),
        );
        assert!(!wants_arrays(&headers));
        let mut taken = reply;
        let arrays: TakenArrays = vec![
            ("ids", ArrayData::U32(std::mem::take(&mut taken.ids))),
            ("values", ArrayData::F64(std::mem::take(&mut taken.values))),
            ("lists", ArrayData::U32Lists(std::mem::take(&mut taken.lists))),
            // An empty array last: a view of length 0 at the body's end.
            ("none", ArrayData::F64(Vec::new())),
        ];
        let body = array_body(&taken, &arrays);
        let (header, read) = read_body(&body);
        assert_eq!(header["name"], "a\"b");
        assert_eq!(header["values"], serde_json::json!([]));
        assert_eq!(read[0], ("ids".to_string(), vec![5.0, 4.0, 3.0]));
        assert_eq!(read[1].1, vec![0.1, -2.5e-300, f64::MAX, 1.0 / 3.0]);
        assert_eq!(read[2].1, vec![0.0, 3.0, 3.0, 4.0, 1.0, 2.0, 3.0, 7.0]);
        assert!(read[3].1.is_empty());
        let header_length = u32::from_le_bytes(body[4..8].try_into().unwrap()) as usize;
        let last = header["binary_arrays"][3]["offset"].as_u64().unwrap() as usize;
        assert_eq!(
            align8(8 + header_length) + last,
            body.len(),
            "the empty array starts at the body's end"
        );
        assert_eq!(body.len() % 8, 0);
    }
}
