//! File fields that are either a built-in name or a full description (`"stairs"` or a scene map,
//! `"jvrc1"` or a robot map). Read by hand rather than as an untagged enum, so that an invalid
//! map reports its own error instead of "data did not match any variant".

use std::marker::PhantomData;

use serde::de::{Deserialize, Deserializer, MapAccess, Visitor};

/// A name, or a value read from a map.
pub(crate) enum NameOr<T> {
    /// A string.
    Name(String),
    /// A map, read as `T`.
    Value(T),
}

struct NameOrVisitor<T> {
    expecting: &'static str,
    marker: PhantomData<T>,
}

impl<'de, T: Deserialize<'de>> Visitor<'de> for NameOrVisitor<T> {
    type Value = NameOr<T>;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(self.expecting)
    }
    fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<NameOr<T>, E> {
        Ok(NameOr::Name(v.to_string()))
    }
    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<NameOr<T>, A::Error> {
        T::deserialize(serde::de::value::MapAccessDeserializer::new(map)).map(NameOr::Value)
    }
}

impl<T> NameOr<T> {
    /// Reads a name or a map; `expecting` says which in the error of anything else.
    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
        expecting: &'static str,
    ) -> Result<Self, D::Error>
    where
        T: Deserialize<'de>,
    {
        d.deserialize_any(NameOrVisitor {
            expecting,
            marker: PhantomData,
        })
    }
}
