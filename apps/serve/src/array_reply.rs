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
//!
//! **Only what changed** (issue 38): each entry carries `hash`, a 64-bit FNV-1a hash of
//! the array's bytes as sent, in 16 hex digits. A client that keeps the arrays of its
//! last replies names them in the request header `X-Sheetform-Held-Arrays:
//! path=hash,…`; an array whose hash it holds is not sent again, its entry marked
//! `"held": true` (its offset is where it would have started, its length its own). A
//! bend drag changes the positions, the flat layout, the triangles (their diagonals
//! follow the bend) and the angle defects, but keeps the rulings' index lists and the
//! pieces: 14 % of a 1 000-ruling reply's bytes.

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

/// The request header naming the arrays a client holds (`path=hash,…`).
pub(crate) const HELD_ARRAYS_HEADER: &str = "x-sheetform-held-arrays";

/// Most `path=hash` pairs read from [`HELD_ARRAYS_HEADER`] (a reply has at most 8 arrays;
/// the rest is ignored).
const MAX_HELD_ARRAYS: usize = 32;

/// The arrays the request says it holds: path and hash, at most [`MAX_HELD_ARRAYS`];
/// malformed pairs are skipped (the array is then sent).
pub(crate) fn held_arrays(headers: &HeaderMap) -> Vec<(String, u64)> {
    headers
        .get_all(HELD_ARRAYS_HEADER)
        .iter()
        .filter_map(|value| value.to_str().ok())
        .flat_map(|value| value.split(','))
        .filter_map(|pair| {
            let (path, hash) = pair.trim().split_once('=')?;
            Some((path.trim().to_string(), u64::from_str_radix(hash.trim(), 16).ok()?))
        })
        .take(MAX_HELD_ARRAYS)
        .collect()
}

/// FNV-1a (64 bits) of bytes fed in order.
struct Fnv1a(u64);

impl Fnv1a {
    fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }

    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
}

/// Hands an array's bytes, as [`array_body`] sends them, to `out` in order: the values
/// little-endian; lists as `length + 1` offsets, then the values.
fn array_bytes(data: &ArrayData, mut out: impl FnMut(&[u8])) {
    match data {
        ArrayData::F64(values) => values.iter().for_each(|v| out(&v.to_le_bytes())),
        ArrayData::U32(values) => values.iter().for_each(|v| out(&v.to_le_bytes())),
        ArrayData::U32Lists(lists) => {
            let mut at = 0u32;
            out(&at.to_le_bytes());
            for list in lists {
                at += list.len() as u32;
                out(&at.to_le_bytes());
            }
            lists.iter().flatten().for_each(|v| out(&v.to_le_bytes()));
        }
    }
}

/// The hash of an array's bytes as [`array_body`] sends them.
fn array_hash(data: &ArrayData) -> u64 {
    let mut hash = Fnv1a::new();
    array_bytes(data, |bytes| hash.bytes(bytes));
    hash.0
}

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
    hash: String,
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    held: bool,
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
/// header, then the `arrays` the client does not hold (`held`: path and hash).
pub(crate) fn array_body<T: Serialize>(reply: &T, arrays: &TakenArrays, held: &[(String, u64)]) -> Vec<u8> {
    let mut entries = Vec::with_capacity(arrays.len());
    let mut sent = Vec::with_capacity(arrays.len());
    let mut offset = 0;
    for (path, data) in arrays {
        let hash = array_hash(data);
        let is_held = held.iter().any(|(p, h)| p == path && *h == hash);
        sent.push(!is_held);
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
            hash: format!("{hash:016x}"),
            held: is_held,
        });
        if !is_held {
            offset = align8(offset + bytes);
        }
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
    for ((_, data), _) in arrays.iter().zip(&sent).filter(|(_, &sent)| sent) {
        array_bytes(data, |bytes| body.extend_from_slice(bytes));
        body.resize(align8(body.len()), 0);
    }
    body
}

/// `reply` as JSON, or, when `headers` ask for it, with the arrays `take` takes out of it
/// in binary (those the request holds left out).
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
        array_body(&reply, &arrays, &held_arrays(headers)),
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
            if entry["held"] == true {
                continue;
            }
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
        let body = array_body(&taken, &arrays, &[]);
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

    /// An array the client holds (same path, same hash) is not sent: its entry says
    /// `held`, the body is shorter by its bytes, and the arrays after it come back
    /// exactly. A stale hash, or another path with the same hash, sends it.
    #[test]
    fn held_arrays_are_not_sent_again() {
        #[derive(Serialize)]
        struct Empty {}
        let arrays = || -> TakenArrays {
            vec![
                ("a", ArrayData::F64(vec![1.0, 2.0, 3.0])),
                ("b", ArrayData::U32(vec![7; 10])),
                ("c", ArrayData::U32Lists(vec![vec![1, 2], vec![3]])),
            ]
        };
        let whole = array_body(&Empty {}, &arrays(), &[]);
        let (header, read) = read_body(&whole);
        let hash_of = |k: usize| u64::from_str_radix(header["binary_arrays"][k]["hash"].as_str().unwrap(), 16).unwrap();
        assert_eq!(hash_of(1), array_hash(&ArrayData::U32(vec![7; 10])));
        let mut headers = HeaderMap::new();
        headers.insert(
            HELD_ARRAYS_HEADER,
            HeaderValue::from_str(&format!("b={:016x}, a=zz, c={:x}", hash_of(1), hash_of(2) ^ 1)).unwrap(),
        );
        let held = held_arrays(&headers);
        assert_eq!(
            held,
            vec![("b".to_string(), hash_of(1)), ("c".to_string(), hash_of(2) ^ 1)]
        );
        let lighter = array_body(&Empty {}, &arrays(), &held);
        let (lighter_header, lighter_read) = read_body(&lighter);
        assert_eq!(lighter_header["binary_arrays"][1]["held"], true);
        assert!(lighter_header["binary_arrays"][0].get("held").is_none());
        assert_eq!(lighter_read, vec![read[0].clone(), read[2].clone()]);
        let data = |body: &[u8]| body.len() - align8(8 + u32::from_le_bytes(body[4..8].try_into().unwrap()) as usize);
        assert_eq!(data(&lighter), data(&whole) - 40, "the ten u32 of `b` are not sent");
        // Held under another path: sent.
        let elsewhere = array_body(&Empty {}, &arrays(), &[("a".to_string(), hash_of(1))]);
        assert_eq!(read_body(&elsewhere).1, read);
    }
}
