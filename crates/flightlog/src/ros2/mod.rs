//! ROS 2 bags: MCAP files whose channels carry `ros2msg` schemas (the `.msg` definition text
//! of the type and, after `====` lines with `MSG: pkg/Type` headers, of every type it
//! nests) and CDR-encoded messages, as rosbag2 and the `mcap-ros2-support` Python package
//! write them.
//!
//! [`bag::read_bag`] reads any MCAP file (whatever complete chunks a truncated one holds),
//! [`summary::summarize`] lists its topics (type, count, rate, time span) and
//! [`summary::export_topic_csv`] writes a topic as CSV with one column per field.
//! Messages are decoded dynamically from the schema text of each channel, so any message
//! type works whose fields are ROS 2's primitive types, strings, nested messages and
//! arrays of these. `cdr.rs` says which crates do the parsing and which part is ours.

pub mod bag;
pub mod cdr;
pub mod idl;
pub mod summary;
#[cfg(test)]
mod tests;
