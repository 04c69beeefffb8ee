//! Decoding a log message into a [`Json`] tree, whatever its encoding: the protobuf messages
//! of today's logs (decoded by the descriptor set embedded in the channel's schema, with
//! prost-reflect) and the JSON messages of logs written before issue #16. The summary, CSV
//! export, Rerun conversion and the re-run check read every log through this tree.
//!
//! Protobuf to tree: fields in the order of the message's descriptor, scalars always (proto3
//! leaves out zeros; they are read back as their default), sub-messages only when present
//! (the `actuation` and `drive` objects of an actuated vehicle), enums as their numbers.
//! A double is written as Rust's shortest text that parses back to the same bits.

use prost_reflect::{DescriptorPool, DynamicMessage, MessageDescriptor, ReflectMessage, Value};

use crate::json::{self, Json};

/// How the messages of one channel are decoded.
#[derive(Debug, Clone)]
pub(crate) enum Decoder {
    /// `json` messages (logs before issue #16).
    Json,
    /// `protobuf` messages of this type.
    Protobuf(MessageDescriptor),
    /// Anything else (the reason, for error messages).
    Unknown(String),
}

impl Decoder {
    /// The decoder of a channel from its message encoding and its schema.
    pub fn new(
        message_encoding: &str,
        schema_name: &str,
        schema_encoding: &str,
        schema_data: &[u8],
    ) -> Self {
        match (message_encoding, schema_encoding) {
            ("json", _) => Decoder::Json,
            ("protobuf", "protobuf") => match DescriptorPool::decode(schema_data) {
                Ok(pool) => match pool.get_message_by_name(schema_name) {
                    Some(d) => Decoder::Protobuf(d),
                    None => Decoder::Unknown(format!(
                        "its schema's descriptor set has no message `{schema_name}`"
                    )),
                },
                Err(e) => Decoder::Unknown(format!("its schema is not a descriptor set: {e}")),
            },
            _ => Decoder::Unknown(format!(
                "message encoding `{message_encoding}` with schema encoding `{schema_encoding}` \
                 (flapwing reads json, and protobuf with protobuf schemas)"
            )),
        }
    }

    /// The message as a tree (`None` if it does not decode).
    pub fn decode(&self, data: &[u8]) -> Option<Json> {
        match self {
            Decoder::Json => json::parse(data).ok(),
            Decoder::Protobuf(d) => DynamicMessage::decode(d.clone(), data)
                .ok()
                .map(|m| message(&m)),
            Decoder::Unknown(_) => None,
        }
    }
}

/// Shortest text of `x` that parses back to the same f64 (`NaN`, `inf`, `-inf` as such).
pub(crate) fn f64_text(x: f64) -> String {
    format!("{x:?}")
}

fn message(m: &DynamicMessage) -> Json {
    let mut fields = Vec::new();
    for f in m.descriptor().fields() {
        let present = m.has_field(&f);
        let is_message = matches!(f.kind(), prost_reflect::Kind::Message(_));
        if is_message && !f.is_list() && !present {
            continue;
        }
        fields.push((f.name().to_owned(), value(&m.get_field(&f))));
    }
    Json::Obj(fields)
}

fn value(v: &Value) -> Json {
    match v {
        Value::Bool(b) => Json::Bool(*b),
        Value::I32(x) => Json::Num(x.to_string()),
        Value::I64(x) => Json::Num(x.to_string()),
        Value::U32(x) => Json::Num(x.to_string()),
        Value::U64(x) => Json::Num(x.to_string()),
        Value::F32(x) => Json::Num(f64_text(f64::from(*x))),
        Value::F64(x) => Json::Num(f64_text(*x)),
        Value::String(s) => Json::Str(s.clone()),
        Value::Bytes(b) => Json::Str(b.iter().map(|x| format!("{x:02x}")).collect()),
        Value::EnumNumber(n) => Json::Num(n.to_string()),
        Value::Message(m) => message(m),
        Value::List(items) => Json::Arr(items.iter().map(value).collect()),
        Value::Map(map) => Json::Obj(
            map.iter()
                .map(|(k, v)| (format!("{k:?}"), value(v)))
                .collect(),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn f64_text_round_trips() {
        for x in [
            0.0,
            -0.0,
            1.0,
            0.1,
            1e-300,
            5e-324,
            f64::MAX,
            -2.5e17,
            f64::INFINITY,
        ] {
            assert_eq!(f64_text(x).parse::<f64>().unwrap().to_bits(), x.to_bits());
        }
        assert!(f64_text(f64::NAN).parse::<f64>().unwrap().is_nan());
    }

    #[test]
    fn protobuf_messages_decode_by_their_embedded_schema() {
        use prost::Message;
        let data = crate::schema::schema_data("flapwing.Controls").unwrap();
        let d = Decoder::new("protobuf", "flapwing.Controls", "protobuf", &data);
        let msg = crate::proto::Controls {
            step: 7,
            freq_hz: 218.5,
            ..Default::default()
        };
        let v = d.decode(&msg.encode_to_vec()).unwrap();
        assert_eq!(v.get("step").and_then(Json::as_u64), Some(7));
        assert_eq!(v.f64_at("freq_hz"), Some(218.5));
        // Zeros are left out on the wire and read back as such; no drive, no `drive` object.
        assert_eq!(v.f64_at("amplitude_deg"), Some(0.0));
        assert!(v.get("drive").is_none());
        let Decoder::Unknown(why) = Decoder::new("protobuf", "flapwing.Nope", "protobuf", &data)
        else {
            panic!("an unknown message name must not decode")
        };
        assert!(why.contains("flapwing.Nope"), "{why}");
        assert!(matches!(
            Decoder::new("cbor", "x", "", b""),
            Decoder::Unknown(_)
        ));
    }
}
