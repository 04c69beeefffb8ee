"""The official ROS 2 message definitions the bag tests write with `mcap-ros2-support`
(its own CDR encoder): shared by test_ros2_bags.py and test_ros2_identify.py."""

# The official definitions, comments dropped: ros2/common_interfaces at
# c0c0bc57f958eb54a142446f0c2a475754367eee (std_msgs/msg/Header.msg, geometry_msgs/msg/
# {PoseStamped,Pose,Point,Quaternion,PoseWithCovariance,TwistWithCovariance,Twist,Vector3,
# TransformStamped,Transform}.msg, std_msgs/msg/{Float64MultiArray,MultiArrayLayout,
# MultiArrayDimension}.msg, nav_msgs/msg/Odometry.msg, sensor_msgs/msg/Imu.msg),
# ros2/geometry2 at 1b005c6556cf350d7670812ef30eefed8443a759 (tf2_msgs/msg/TFMessage.msg) and
# ros2/rcl_interfaces at f6b3741d921ef5414125091b2ccc74b863be3c24 (builtin_interfaces/msg/
# Time.msg).
DEFS = {
    "builtin_interfaces/Time": "int32 sec\nuint32 nanosec\n",
    "std_msgs/Header": "builtin_interfaces/Time stamp\nstring frame_id\n",
    "geometry_msgs/Point": "float64 x\nfloat64 y\nfloat64 z\n",
    "geometry_msgs/Quaternion": "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n",
    "geometry_msgs/Vector3": "float64 x\nfloat64 y\nfloat64 z\n",
    "geometry_msgs/Pose": "Point position\nQuaternion orientation\n",
    "geometry_msgs/PoseStamped": "std_msgs/Header header\nPose pose\n",
    "geometry_msgs/PoseWithCovariance": "Pose pose\nfloat64[36] covariance\n",
    "geometry_msgs/Twist": "Vector3  linear\nVector3  angular\n",
    "geometry_msgs/TwistWithCovariance": "Twist twist\nfloat64[36] covariance\n",
    "geometry_msgs/Transform": "Vector3 translation\nQuaternion rotation\n",
    "geometry_msgs/TransformStamped": "std_msgs/Header header\nstring child_frame_id\nTransform transform\n",
    "nav_msgs/Odometry": (
        "# This represents an estimate of a position and velocity in free space.\n"
        "std_msgs/Header header\n\nstring child_frame_id\n\n"
        "geometry_msgs/PoseWithCovariance pose\n\ngeometry_msgs/TwistWithCovariance twist\n"
    ),
    "tf2_msgs/TFMessage": "geometry_msgs/TransformStamped[] transforms\n",
    "std_msgs/MultiArrayDimension": "string label\nuint32 size\nuint32 stride\n",
    "std_msgs/MultiArrayLayout": "MultiArrayDimension[] dim\nuint32 data_offset\n",
    "std_msgs/Float64MultiArray": "MultiArrayLayout layout\nfloat64[] data\n",
    "sensor_msgs/Imu": (
        "std_msgs/Header header\ngeometry_msgs/Quaternion orientation\n"
        "float64[9] orientation_covariance # Row major about x, y, z axes\n"
        "geometry_msgs/Vector3 angular_velocity\n"
        "float64[9] angular_velocity_covariance # Row major about x, y, z axes\n"
        "geometry_msgs/Vector3 linear_acceleration\n"
        "float64[9] linear_acceleration_covariance # Row major x, y z\n"
    ),
}
DEPS = {
    "geometry_msgs/PoseStamped": ["std_msgs/Header", "builtin_interfaces/Time", "geometry_msgs/Pose",
                                  "geometry_msgs/Point", "geometry_msgs/Quaternion"],
    "nav_msgs/Odometry": ["std_msgs/Header", "builtin_interfaces/Time", "geometry_msgs/PoseWithCovariance",
                          "geometry_msgs/Pose", "geometry_msgs/Point", "geometry_msgs/Quaternion",
                          "geometry_msgs/TwistWithCovariance", "geometry_msgs/Twist", "geometry_msgs/Vector3"],
    "tf2_msgs/TFMessage": ["geometry_msgs/TransformStamped", "std_msgs/Header", "builtin_interfaces/Time",
                           "geometry_msgs/Transform", "geometry_msgs/Vector3", "geometry_msgs/Quaternion"],
    "std_msgs/Float64MultiArray": ["std_msgs/MultiArrayLayout", "std_msgs/MultiArrayDimension"],
    "sensor_msgs/Imu": ["std_msgs/Header", "builtin_interfaces/Time", "geometry_msgs/Quaternion",
                        "geometry_msgs/Vector3"],
}
T0_NS = 1_700_000_000_123_456_789


def schema_text(name):
    """rosbag2's layout: the type's text, then each nested type after a `===` line."""
    parts = [DEFS[name]]
    for dep in DEPS[name]:
        parts.append("=" * 80 + f"\nMSG: {dep}\n" + DEFS[dep])
    return "\n".join(parts)


def register(w, short):
    pkg, typ = short.split("/")
    return w.register_msgdef(f"{pkg}/msg/{typ}", schema_text(short))


def stamp(t_ns):
    return {"sec": t_ns // 10**9, "nanosec": t_ns % 10**9}
