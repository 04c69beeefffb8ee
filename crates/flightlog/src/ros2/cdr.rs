//! A ROS 2 message type read from a `ros2msg` schema, and its CDR messages decoded into
//! flat `(dotted.field.path, text)` pairs in definition order.
//!
//! The `.msg` text is parsed by Rerun's `re_ros_msg` and the CDR primitives (byte order,
//! alignment, strings, sequence lengths) are read by its `re_cdr::CdrReader`. The walk over
//! the fields is ours, because `re_ros_msg::deserialize::decode_message` returns each
//! message's fields in a `BTreeMap` (alphabetical, so a CSV's columns would lose the
//! definition's order) and its errors do not say which field failed ("unexpected end of
//! input"); here every error names the field path and its type.
//!
//! Wire format (OMG CDR, DDS-XTypes 1.3 section 7.4.3.4, "XCDR1", which ROS 2's rmw layers
//! write): a 4-byte encapsulation header (representation identifier, big-endian u16, then
//! two option bytes), then the fields in order, each primitive aligned to its own size
//! (1, 2, 4 or 8 bytes) counted from the end of the header; strings and sequences are a
//! u32 length then the elements (strings with their terminating NUL); fixed arrays are the
//! elements alone.

use std::collections::HashMap;

use re_cdr::{BigEndian, CdrEndian, CdrReader, LittleEndian};
use re_ros_msg::MessageSchema;
use re_ros_msg::message_spec::{
    ArraySize, BuiltInType, ComplexType, MessageSpecification, Type, message_package,
};

/// Arrays of primitives longer than this become one `name.length` column instead of one
/// column per element (an image's pixels would otherwise be a million columns).
pub const MAX_ARRAY_COLUMNS: usize = 64;

/// Nesting deeper than this is refused (a schema whose types contain themselves).
const MAX_DEPTH: usize = 32;

/// What the field types may be, for error messages.
const ALLOWED: &str = "allowed: bool, byte, char, int8-int64, uint8-uint64, float32, float64, \
                       string, nested messages the schema defines, and arrays of these";

/// `builtin_interfaces` types that every ROS 2 distribution defines, used when a schema
/// refers to them without including their text.
const BUILTIN_TYPES: [(&str, &str); 2] = [
    ("builtin_interfaces/Time", "int32 sec\nuint32 nanosec\n"),
    ("builtin_interfaces/Duration", "int32 sec\nuint32 nanosec\n"),
];

/// `pkg/Type` for `pkg/Type` and `pkg/msg/Type`.
fn normalized(package: &str, name: &str) -> String {
    format!("{}/{name}", package.trim_end_matches("/msg"))
}

fn normalized_full(full: &str) -> String {
    match full.rsplit_once('/') {
        Some((package, name)) => normalized(package, name),
        None => full.to_owned(),
    }
}

/// A message type ready to decode its messages.
#[derive(Debug, Clone)]
pub struct MessageType {
    /// Its name, as the schema gives it (`geometry_msgs/msg/PoseStamped`).
    pub name: String,
    main: MessageSpecification,
    /// Every other type, by `pkg/Type`.
    types: HashMap<String, MessageSpecification>,
}

fn type_text(ty: &Type) -> String {
    match ty {
        Type::BuiltIn(b) => builtin_text(b).to_owned(),
        Type::Complex(ComplexType::Absolute { package, name }) => format!("{package}/{name}"),
        Type::Complex(ComplexType::Relative { name }) => name.clone(),
        Type::Array { ty, size } => match size {
            ArraySize::Fixed(n) => format!("{}[{n}]", type_text(ty)),
            ArraySize::Bounded(n) => format!("{}[<={n}]", type_text(ty)),
            ArraySize::Unbounded => format!("{}[]", type_text(ty)),
        },
    }
}

fn builtin_text(b: &BuiltInType) -> &'static str {
    match b {
        BuiltInType::Bool => "bool",
        BuiltInType::Byte => "byte",
        BuiltInType::Char => "char",
        BuiltInType::Float32 => "float32",
        BuiltInType::Float64 => "float64",
        BuiltInType::Int8 => "int8",
        BuiltInType::Int16 => "int16",
        BuiltInType::Int32 => "int32",
        BuiltInType::Int64 => "int64",
        BuiltInType::UInt8 => "uint8",
        BuiltInType::UInt16 => "uint16",
        BuiltInType::UInt32 => "uint32",
        BuiltInType::UInt64 => "uint64",
        BuiltInType::String(_) => "string",
        BuiltInType::WString(_) => "wstring",
    }
}

fn join(prefix: &str, name: &str) -> String {
    if prefix.is_empty() {
        name.to_owned()
    } else {
        format!("{prefix}.{name}")
    }
}

impl MessageType {
    /// Parses the schema text of type `name` (the main definition, then each dependency
    /// after a `====` line and a `MSG: pkg/Type` line) and checks that every nested type is
    /// defined and decodable. The error says which field is at fault and what is allowed.
    pub fn parse(name: &str, text: &str) -> Result<Self, String> {
        let schema = MessageSchema::parse(name, text)
            .map_err(|e| format!("the message definition does not parse: {e:#}"))?;
        let mut types = HashMap::new();
        for (full, body) in BUILTIN_TYPES {
            let spec = MessageSchema::parse(full, body)
                .map_err(|e| format!("built-in `{full}` does not parse: {e:#}"))?;
            types.insert(full.to_owned(), spec.spec);
        }
        for dep in schema.dependencies {
            types.insert(normalized_full(&dep.name), dep);
        }
        let t = MessageType {
            name: name.to_owned(),
            main: schema.spec,
            types,
        };
        t.check(&t.main, "", 0)?;
        Ok(t)
    }

    fn resolve(
        &self,
        scope: &MessageSpecification,
        ty: &ComplexType,
    ) -> Option<&MessageSpecification> {
        let key = match ty {
            ComplexType::Absolute { package, name } => normalized(package, name),
            ComplexType::Relative { name } => match message_package(&scope.name) {
                Some(package) => format!("{package}/{name}"),
                None => name.clone(),
            },
        };
        self.types.get(&key)
    }

    fn defined(&self) -> String {
        let mut names: Vec<&str> = self.types.keys().map(String::as_str).collect();
        names.sort_unstable();
        names.join(", ")
    }

    fn check(&self, spec: &MessageSpecification, prefix: &str, depth: usize) -> Result<(), String> {
        if depth > MAX_DEPTH {
            return Err(format!(
                "field `{prefix}` nests more than {MAX_DEPTH} messages deep (a type that \
                 contains itself?)"
            ));
        }
        for f in &spec.fields {
            let path = join(prefix, &f.name);
            let mut ty = &f.ty;
            while let Type::Array { ty: inner, .. } = ty {
                ty = inner;
            }
            match ty {
                Type::BuiltIn(BuiltInType::WString(_)) => {
                    return Err(format!(
                        "field `{path}` is a `{}`, whose UTF-16 wire form is not supported \
                         ({ALLOWED})",
                        type_text(&f.ty)
                    ));
                }
                Type::Complex(c) => {
                    let Some(inner) = self.resolve(spec, c) else {
                        return Err(format!(
                            "field `{path}` has type `{}`, which the schema does not define \
                             (it defines {}; {ALLOWED})",
                            type_text(&f.ty),
                            self.defined()
                        ));
                    };
                    if inner
                        .underlying_type_if_enum_like()
                        .map_err(|e| format!("field `{path}`: {e}"))?
                        .is_none()
                    {
                        self.check(inner, &path, depth + 1)?;
                    }
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// Decodes one CDR message (encapsulation header included) into `(field path, text)`
    /// pairs in definition order: numbers as Rust prints them (floats round-trip exactly),
    /// booleans as true/false, strings as they are; array elements as `name.0`, `name.1`...
    /// The error names the field that could not be read and why.
    pub fn decode(&self, data: &[u8]) -> Result<Vec<(String, String)>, String> {
        if data.len() < 4 {
            return Err(format!(
                "the message is {} bytes, shorter than the 4-byte CDR encapsulation header",
                data.len()
            ));
        }
        let id = u16::from_be_bytes([data[0], data[1]]);
        let mut out = Vec::new();
        let body = &data[4..];
        let result = match id {
            0x0000 => self.walk(
                &mut CdrReader::<BigEndian>::new(body),
                &self.main,
                "",
                &mut out,
            ),
            0x0001 => self.walk(
                &mut CdrReader::<LittleEndian>::new(body),
                &self.main,
                "",
                &mut out,
            ),
            other => {
                return Err(format!(
                    "the CDR encapsulation is 0x{other:04x}, not supported (allowed: 0x0000 \
                     CDR_BE and 0x0001 CDR_LE, plain CDR as ROS 2 writes it)"
                ));
            }
        };
        result.map(|()| out).map_err(|(path, ty, pos, e)| {
            let why = match e {
                re_cdr::Error::UnexpectedEof => format!(
                    "the message ends first ({} bytes; {} read before this field)",
                    data.len(),
                    pos + 4
                ),
                other => other.to_string(),
            };
            format!("field `{path}` ({ty}) cannot be read: {why}")
        })
    }

    fn walk<BO: CdrEndian>(
        &self,
        r: &mut CdrReader<'_, BO>,
        spec: &MessageSpecification,
        prefix: &str,
        out: &mut Vec<(String, String)>,
    ) -> Result<(), (String, String, usize, re_cdr::Error)> {
        for f in &spec.fields {
            self.value(r, spec, &f.ty, &join(prefix, &f.name), out)?;
        }
        Ok(())
    }

    fn value<BO: CdrEndian>(
        &self,
        r: &mut CdrReader<'_, BO>,
        scope: &MessageSpecification,
        ty: &Type,
        path: &str,
        out: &mut Vec<(String, String)>,
    ) -> Result<(), (String, String, usize, re_cdr::Error)> {
        let fail = |r: &CdrReader<'_, BO>, e| (path.to_owned(), type_text(ty), r.position(), e);
        match ty {
            Type::BuiltIn(b) => {
                let text = scalar(r, b).map_err(|e| fail(r, e))?;
                out.push((path.to_owned(), text));
            }
            Type::Complex(c) => {
                // `parse` checked that every type resolves.
                let Some(spec) = self.resolve(scope, c) else {
                    return Err(fail(r, re_cdr::Error::Custom("undefined type".into())));
                };
                match spec.underlying_type_if_enum_like() {
                    Ok(Some(b)) => {
                        let text = scalar(r, b).map_err(|e| fail(r, e))?;
                        out.push((path.to_owned(), text));
                    }
                    _ => self.walk(r, spec, path, out)?,
                }
            }
            Type::Array { ty: elem, size } => {
                let count = match size {
                    ArraySize::Fixed(n) => *n,
                    ArraySize::Bounded(_) | ArraySize::Unbounded => {
                        r.read_sequence_length().map_err(|e| fail(r, e))?
                    }
                };
                if let ArraySize::Bounded(max) = size
                    && count > *max
                {
                    let msg = format!("{count} elements, more than the bound {max}");
                    return Err(fail(r, re_cdr::Error::Custom(msg)));
                }
                if let Type::BuiltIn(b) = elem.as_ref()
                    && count > MAX_ARRAY_COLUMNS
                {
                    for _ in 0..count {
                        scalar(r, b).map_err(|e| fail(r, e))?;
                    }
                    out.push((join(path, "length"), count.to_string()));
                } else {
                    for i in 0..count {
                        self.value(r, scope, elem, &join(path, &i.to_string()), out)?;
                    }
                }
            }
        }
        Ok(())
    }
}

fn scalar<BO: CdrEndian>(r: &mut CdrReader<'_, BO>, b: &BuiltInType) -> re_cdr::Result<String> {
    Ok(match b {
        BuiltInType::Bool => r.read_bool()?.to_string(),
        BuiltInType::Byte | BuiltInType::Char | BuiltInType::UInt8 => r.read_u8()?.to_string(),
        BuiltInType::Int8 => r.read_i8()?.to_string(),
        BuiltInType::Int16 => r.read_i16()?.to_string(),
        BuiltInType::UInt16 => r.read_u16()?.to_string(),
        BuiltInType::Int32 => r.read_i32()?.to_string(),
        BuiltInType::UInt32 => r.read_u32()?.to_string(),
        BuiltInType::Int64 => r.read_i64()?.to_string(),
        BuiltInType::UInt64 => r.read_u64()?.to_string(),
        // Debug prints the shortest text that reads back to the same value, with an
        // exponent for large and small magnitudes (Display would print 1e300 in full).
        BuiltInType::Float32 => format!("{:?}", r.read_f32()?),
        BuiltInType::Float64 => format!("{:?}", r.read_f64()?),
        BuiltInType::String(_) => r.read_string()?,
        BuiltInType::WString(_) => {
            return Err(re_cdr::Error::Custom(format!(
                "wstring is not supported ({ALLOWED})"
            )));
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "int8 a\nfloat64 b # a comment\nstring s\nuint16[] v\nbool f\nInner inner\n\
                        float32[2] fixed\nint32 CONST=7\n\
                        ================================================================\n\
                        MSG: my_pkg/Inner\nint32 k\n";

    /// The message of [`TEXT`] laid out by hand per OMG CDR (DDS-XTypes 1.3, 7.4.3.4; the
    /// encapsulation header 7.6.3.1.2): each primitive aligned to its size from the end of
    /// the 4-byte header, strings and sequences a u32 length first, strings NUL-terminated.
    fn message(little: bool) -> Vec<u8> {
        let mut b = vec![0x00, if little { 0x01 } else { 0x00 }, 0x00, 0x00];
        let mut body: Vec<u8> = Vec::new();
        macro_rules! put {
            ($v:expr) => {{
                let v = $v;
                let bytes = if little {
                    v.to_le_bytes().to_vec()
                } else {
                    v.to_be_bytes().to_vec()
                };
                while body.len() % bytes.len() != 0 {
                    body.push(0);
                }
                body.extend_from_slice(&bytes);
            }};
        }
        put!(-3i8); // a at 0
        put!(0.1f64); // b at 8 (7 bytes of padding)
        put!(3u32); // s: length 3 at 16
        body.extend_from_slice(b"hi\0"); // 20..23
        put!(2u32); // v: 2 elements at 24
        put!(65535u16); // 28
        put!(7u16); // 30
        body.push(1); // f at 32
        put!(-123456i32); // inner.k at 36
        put!(1.5f32); // fixed.0 at 40
        put!(-2.25e-9f32); // fixed.1 at 44
        b.extend_from_slice(&body);
        b
    }

    #[test]
    fn decodes_hand_made_cdr_in_both_byte_orders() {
        let t = MessageType::parse("my_pkg/msg/Thing", TEXT).unwrap();
        let want: Vec<(String, String)> = [
            ("a", "-3"),
            ("b", "0.1"),
            ("s", "hi"),
            ("v.0", "65535"),
            ("v.1", "7"),
            ("f", "true"),
            ("inner.k", "-123456"),
            ("fixed.0", "1.5"),
            ("fixed.1", "-2.25e-9"),
        ]
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
        for little in [true, false] {
            let m = message(little);
            assert_eq!(m.len(), 4 + 48);
            assert_eq!(t.decode(&m).unwrap(), want, "little endian {little}");
        }
    }

    #[test]
    fn every_cut_names_a_field_and_nothing_panics() {
        let t = MessageType::parse("my_pkg/msg/Thing", TEXT).unwrap();
        let m = message(true);
        for n in 0..m.len() {
            let e = t.decode(&m[..n]).unwrap_err();
            if n < 4 {
                assert!(e.contains("4-byte CDR encapsulation header"), "{e}");
            } else {
                assert!(
                    e.starts_with("field `") && e.contains("the message ends first"),
                    "{e}"
                );
            }
        }
        // The cut inside the nested message names its path.
        let e = t.decode(&m[..4 + 38]).unwrap_err();
        assert!(e.starts_with("field `inner.k` (int32)"), "{e}");
        // An encapsulation other than plain CDR.
        let mut x = m.clone();
        x[1] = 0x07;
        assert!(t.decode(&x).unwrap_err().contains("0x0007"));
        // A bool that is neither 0 nor 1.
        let mut x = m;
        x[4 + 32] = 9;
        assert!(t.decode(&x).unwrap_err().starts_with("field `f` (bool)"));
    }

    #[test]
    fn bad_schemas_are_refused_with_the_field() {
        let e = MessageType::parse("p/msg/T", "int32 a\nOther b\n").unwrap_err();
        assert!(
            e.contains("field `b` has type `Other`") && e.contains("allowed:"),
            "{e}"
        );
        let e = MessageType::parse("p/msg/T", "wstring w\n").unwrap_err();
        assert!(e.contains("field `w` is a `wstring`"), "{e}");
        let e = MessageType::parse("p/msg/T", "int32[ a\n").unwrap_err();
        assert!(e.contains("does not parse"), "{e}");
        // builtin_interfaces/Time is known without its text.
        let t = MessageType::parse("p/msg/T", "builtin_interfaces/Time t\n").unwrap();
        let m = [0, 1, 0, 0, 5, 0, 0, 0, 9, 0, 0, 0];
        assert_eq!(t.decode(&m).unwrap()[1], ("t.nanosec".into(), "9".into()));
    }
}
