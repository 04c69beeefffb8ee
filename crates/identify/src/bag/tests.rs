//! The roles file: every table read, bad fields named.

use super::roles::BagRoles;
use super::topics::normalized;
use crate::conventions::{BodyConvention, QuaternionOrder, WorldConvention};

#[test]
fn a_roles_file_reads_every_table() {
    let r = BagRoles::from_toml(
        r#"
time_origin_ns = 12
[pose]
topic = "/tf"
child_frame = "fly"
[imu]
topic = "/imu"
body = "frd"
[controls]
topic = "/drive"
fields = { amplitude_rad = "data.1" }
[frames]
world = "ned"
quaternion = "wxyz"
"#,
        "roles.toml",
    )
    .unwrap();
    assert_eq!(r.time_origin_ns, Some(12));
    assert_eq!(r.pose.as_ref().unwrap().child_frame.as_deref(), Some("fly"));
    assert_eq!(r.imu.as_ref().unwrap().body, Some(BodyConvention::Frd));
    assert_eq!(
        r.controls.as_ref().unwrap().fields["amplitude_rad"],
        "data.1"
    );
    assert_eq!(r.frames.world, WorldConvention::Ned);
    assert_eq!(r.frames.body, BodyConvention::Flu, "the default body frame");
    assert_eq!(r.frames.quaternion, QuaternionOrder::Wxyz);
    assert_eq!(
        r.describe(),
        "pose /tf, IMU /imu, controls /drive; world NED, body FLU, quaternion wxyz"
    );
}

#[test]
fn a_bad_roles_file_names_the_file_the_field_and_what_is_allowed() {
    for (text, names) in [
        ("[pose]\ntopik = \"/p\"\n", "topik"),
        ("[frames]\nworld = \"nwu\"\n", "nwu"),
        ("[cameras]\n", "cameras"),
    ] {
        let e = BagRoles::from_toml(text, "r.toml").unwrap_err().to_string();
        assert!(
            e.contains("roles file `r.toml`") && e.contains(names),
            "{e}"
        );
        assert!(e.contains("world = \"enu\"|\"ned\""), "{e}");
    }
}

#[test]
fn type_names_of_both_spellings_match() {
    assert_eq!(
        normalized("geometry_msgs/PoseStamped"),
        "geometry_msgs/msg/PoseStamped"
    );
    assert_eq!(
        normalized("geometry_msgs/msg/PoseStamped"),
        "geometry_msgs/msg/PoseStamped"
    );
}
