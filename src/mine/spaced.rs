//! Rod lists as one space-separated string, which keeps the JSON of a
//! report's examples short: serde's `with` for a list, `serialize_with`
//! and `deserialize_with` for an optional one.

use serde::{Deserialize, Deserializer, Serializer, de::Error};

pub(super) fn serialize<S: Serializer>(rods: &[u32], s: S) -> Result<S::Ok, S::Error> {
    let words: Vec<String> = rods.iter().map(u32::to_string).collect();
    s.serialize_str(&words.join(" "))
}

pub(super) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<u32>, D::Error> {
    String::deserialize(d)?
        .split_whitespace()
        .map(|w| w.parse().map_err(D::Error::custom))
        .collect()
}

/// [`serialize`] for an optional list.
pub(super) fn serialize_opt<S: Serializer>(
    rods: &Option<Vec<u32>>,
    s: S,
) -> Result<S::Ok, S::Error> {
    match rods {
        Some(r) => serialize(r, s),
        None => s.serialize_none(),
    }
}

/// [`deserialize`] for an optional list.
pub(super) fn deserialize_opt<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<Vec<u32>>, D::Error> {
    #[derive(Deserialize)]
    struct Wrap(#[serde(deserialize_with = "deserialize")] Vec<u32>);
    Ok(Option::<Wrap>::deserialize(d)?.map(|Wrap(r)| r))
}
