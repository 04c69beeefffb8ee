//! ROS 2 IDL schemas (`ros2idl`): what rosbag2 writes for a type defined in IDL rather than
//! in a `.msg` file. The schema data is the type's IDL text, then each dependency's after a
//! line of `=` and an `IDL: pkg/msg/Type` line.
//!
//! Each section is parsed by the `ros2msg` crate's IDL parser (typedefs resolved, includes
//! and annotations read past), and every structure is written back as the `.msg` text of
//! the same fields; [`super::cdr::MessageType`] then reads the bundle as any `ros2msg`
//! schema. That is sound because CDR, the wire format, depends on the fields' types and
//! order alone, not on the language that declared them. The translation is ours (no crate
//! decodes CDR from an IDL parse: `ros2msg` parses, Rerun's `re_ros_msg`, which the `.msg`
//! path uses, reads `.msg` only). Types a `.msg` cannot state (`long double`, `wchar`,
//! arrays of arrays) are refused by name.

use ros2msg::idl::{
    AbstractString, AbstractWString, BasicTypeKind, IdlContentElement, IdlType, Structure,
};

/// The schema encoding of ROS 2 IDL definitions.
pub const SCHEMA_ROS2IDL: &str = "ros2idl";

/// The `.msg` separator line between a bundle's definitions.
const MSG_SEPARATOR: &str =
    "================================================================================";

/// The `ros2msg` bundle equivalent to the `ros2idl` schema `idl` of type `name`
/// (`pkg/msg/Type`): the main type's `.msg` text, then each other structure's after a
/// separator and `MSG: pkg/Type`. The error names the section, the field and the type.
pub fn msg_bundle(name: &str, idl: &str) -> Result<String, String> {
    let mut structs: Vec<Structure> = Vec::new();
    for (k, section) in sections(idl).iter().enumerate() {
        let file = ros2msg::idl::parse_idl_string(section)
            .map_err(|e| format!("IDL section {} does not parse: {e}", k + 1))?;
        for e in file.content.elements {
            match e {
                IdlContentElement::Message(m) => structs.push(m.structure),
                IdlContentElement::Structure(s) => structs.push(s),
                _ => {}
            }
        }
    }
    let (pkg, type_name) = split_name(name);
    let main = structs
        .iter()
        .position(|s| {
            s.namespaced_type.name == type_name
                && s.namespaced_type.namespaces.first().map(String::as_str) == Some(pkg)
        })
        .ok_or_else(|| {
            format!(
                "the IDL defines no structure `{name}` (it defines: {})",
                structs
                    .iter()
                    .map(|s| s.namespaced_type.full_name("::"))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })?;
    let mut out = msg_text(&structs[main])?;
    for (k, s) in structs.iter().enumerate() {
        if k != main {
            let t = &s.namespaced_type;
            let pkg = t.namespaces.first().map_or("", String::as_str);
            out.push_str(&format!("{MSG_SEPARATOR}\nMSG: {pkg}/{}\n", t.name));
            out.push_str(&msg_text(s)?);
        }
    }
    Ok(out)
}

/// The bundle's sections: split at each separator line of `=` followed by an `IDL:` line.
fn sections(idl: &str) -> Vec<String> {
    let mut out = vec![String::new()];
    let mut lines = idl.lines().peekable();
    while let Some(line) = lines.next() {
        let t = line.trim();
        if t.len() >= 3
            && t.chars().all(|c| c == '=')
            && lines
                .peek()
                .is_some_and(|next| next.trim_start().starts_with("IDL:"))
        {
            lines.next();
            out.push(String::new());
            continue;
        }
        let last = out.len() - 1;
        out[last].push_str(line);
        out[last].push('\n');
    }
    out.retain(|s| !s.trim().is_empty());
    out
}

/// (`pkg`, `Type`) of `pkg/msg/Type` (or `pkg/Type`).
fn split_name(name: &str) -> (&str, &str) {
    let pkg = name.split('/').next().unwrap_or("");
    let ty = name.rsplit('/').next().unwrap_or(name);
    (pkg, ty)
}

/// A structure's fields as `.msg` lines.
fn msg_text(s: &Structure) -> Result<String, String> {
    let pkg = s
        .namespaced_type
        .namespaces
        .first()
        .map_or("", String::as_str);
    let mut out = String::new();
    for m in &s.members {
        let ty = msg_type(&m.member_type, pkg).map_err(|e| {
            format!(
                "field `{}` of `{}`: {e}",
                m.name,
                s.namespaced_type.full_name("::")
            )
        })?;
        out.push_str(&format!("{ty} {}\n", m.name));
    }
    Ok(out)
}

/// The `.msg` spelling of an IDL type (inside package `pkg`).
fn msg_type(t: &IdlType, pkg: &str) -> Result<String, String> {
    let element = |t: &IdlType| -> Result<String, String> {
        match t {
            IdlType::Array(_) | IdlType::BoundedSequence(_) | IdlType::UnboundedSequence(_) => {
                Err("an array of arrays, which a .msg cannot state".into())
            }
            t => msg_type(t, pkg),
        }
    };
    Ok(match t {
        IdlType::Basic(b) => basic(b.kind)?.to_owned(),
        IdlType::Namespaced(n) => {
            let p = n.namespaces.first().map_or(pkg, String::as_str);
            format!("{p}/{}", n.name)
        }
        IdlType::Named(n) => format!("{pkg}/{}", n.name()),
        IdlType::String(AbstractString::Unbounded(_)) => "string".into(),
        IdlType::String(AbstractString::Bounded(b)) => format!("string<={}", b.maximum_size),
        IdlType::WString(AbstractWString::Unbounded(_)) => "wstring".into(),
        IdlType::WString(AbstractWString::Bounded(b)) => format!("wstring<={}", b.maximum_size),
        IdlType::Array(a) => format!("{}[{}]", element(&a.value_type)?, a.size),
        IdlType::BoundedSequence(s) => {
            format!("{}[<={}]", element(&s.value_type)?, s.maximum_size)
        }
        IdlType::UnboundedSequence(s) => format!("{}[]", element(&s.value_type)?),
    })
}

/// The `.msg` name of an IDL basic type.
fn basic(kind: BasicTypeKind) -> Result<&'static str, String> {
    use BasicTypeKind as K;
    Ok(match kind {
        K::Int8 => "int8",
        K::Int16 | K::Short => "int16",
        K::Int32 | K::Int | K::Long => "int32",
        K::Int64 | K::LongLong => "int64",
        K::UInt8 => "uint8",
        K::UInt16 | K::UnsignedShort => "uint16",
        K::UInt32 | K::UnsignedLong => "uint32",
        K::UInt64 | K::UnsignedLongLong => "uint64",
        K::Float => "float32",
        K::Double => "float64",
        K::Char => "char",
        K::Boolean => "bool",
        K::Octet => "byte",
        K::LongDouble | K::WChar => {
            return Err(format!(
                "IDL type `{}` has no .msg equivalent (allowed: the integer, float, double, char, boolean and octet types, strings, nested structures and their arrays and sequences)",
                kind.as_str()
            ));
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// geometry_msgs/msg/PoseWithCovarianceStamped as rosidl writes its IDL (a typedef'd
    /// array, annotations, includes), with its dependencies in the bundle.
    const IDL: &str = r#"// generated from rosidl_adapter/resource/msg.idl.em
#include "geometry_msgs/msg/PoseWithCovariance.idl"
#include "std_msgs/msg/Header.idl"

module geometry_msgs {
  module msg {
    @verbatim (language="comment", text=
      "This expresses an estimated pose with a reference coordinate frame and timestamp")
    struct PoseWithCovarianceStamped {
      std_msgs::msg::Header header;

      geometry_msgs::msg::PoseWithCovariance pose;
    };
  };
};
================================================================================
IDL: geometry_msgs/msg/PoseWithCovariance
module geometry_msgs {
  module msg {
    typedef double double__36[36];
    struct PoseWithCovariance {
      geometry_msgs::msg::Pose pose;

      @verbatim (language="comment", text="Row-major representation of the 6x6 covariance matrix")
      double__36 covariance;
    };
  };
};
================================================================================
IDL: geometry_msgs/msg/Pose
module geometry_msgs {
  module msg {
    struct Pose {
      geometry_msgs::msg::Point position;
      geometry_msgs::msg::Quaternion orientation;
    };
  };
};
================================================================================
IDL: geometry_msgs/msg/Point
module geometry_msgs {
  module msg {
    struct Point {
      double x;
      double y;
      double z;
    };
  };
};
================================================================================
IDL: geometry_msgs/msg/Quaternion
module geometry_msgs {
  module msg {
    struct Quaternion {
      @default (value=0.0)
      double x;
      @default (value=0.0)
      double y;
      @default (value=0.0)
      double z;
      @default (value=1.0)
      double w;
    };
  };
};
================================================================================
IDL: std_msgs/msg/Header
module std_msgs {
  module msg {
    struct Header {
      builtin_interfaces::msg::Time stamp;
      string frame_id;
    };
  };
};
"#;

    /// The bundle reads as the `.msg` definitions of the same type: the same columns in the
    /// same order as the official `.msg` text gives.
    #[test]
    fn an_idl_bundle_reads_as_its_msg_definitions() {
        let bundle = msg_bundle("geometry_msgs/msg/PoseWithCovarianceStamped", IDL).unwrap();
        assert!(
            bundle.starts_with("std_msgs/Header header\ngeometry_msgs/PoseWithCovariance pose\n")
        );
        assert!(bundle.contains("MSG: geometry_msgs/PoseWithCovariance\ngeometry_msgs/Pose pose\nfloat64[36] covariance\n"));
        let from_idl = super::super::cdr::MessageType::parse(
            "geometry_msgs/msg/PoseWithCovarianceStamped",
            &bundle,
        )
        .unwrap();
        let msg = "std_msgs/Header header\ngeometry_msgs/PoseWithCovariance pose\n\
                   ================================================================================\n\
                   MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n\
                   ================================================================================\n\
                   MSG: geometry_msgs/PoseWithCovariance\ngeometry_msgs/Pose pose\nfloat64[36] covariance\n\
                   ================================================================================\n\
                   MSG: geometry_msgs/Pose\ngeometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n\
                   ================================================================================\n\
                   MSG: geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z\n\
                   ================================================================================\n\
                   MSG: geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w\n";
        let from_msg = super::super::cdr::MessageType::parse(
            "geometry_msgs/msg/PoseWithCovarianceStamped",
            msg,
        )
        .unwrap();
        // One message, little-endian CDR: stamp, frame_id, then 7 + 36 doubles.
        let mut data = vec![0u8, 1, 0, 0];
        data.extend(7i32.to_le_bytes());
        data.extend(9u32.to_le_bytes());
        data.extend(6u32.to_le_bytes());
        data.extend(b"world\0");
        while (data.len() - 4) % 8 != 0 {
            data.push(0);
        }
        for k in 0..43 {
            data.extend((k as f64 * 0.5).to_le_bytes());
        }
        let a = from_idl.decode(&data).unwrap();
        assert_eq!(a, from_msg.decode(&data).unwrap());
        assert_eq!(
            a[2],
            ("header.frame_id".to_owned(), "world".to_owned()),
            "{a:?}"
        );
        assert_eq!(a.len(), 3 + 43);
    }

    #[test]
    fn types_a_msg_cannot_state_are_named() {
        let idl = "module p { module msg { struct T { long double a; }; }; };";
        let e = msg_bundle("p/msg/T", idl).unwrap_err();
        assert!(
            e.contains("field `a` of `p::msg::T`") && e.contains("long double"),
            "{e}"
        );
        let e = msg_bundle("p/msg/U", idl).unwrap_err();
        assert!(
            e.contains("no structure `p/msg/U`") && e.contains("p::msg::T"),
            "{e}"
        );
        let e = msg_bundle("p/msg/T", "module p { struct").unwrap_err();
        assert!(e.contains("IDL section 1 does not parse"), "{e}");
    }
}
