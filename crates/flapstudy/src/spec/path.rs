//! Factor paths: `a.b[2].c` parsed into steps, and a numeric field of a model's TOML table
//! set at such a path.

/// One step of a factor path.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PathStep {
    /// A table key.
    Key(String),
    /// An array index.
    Index(usize),
}

/// Parses `a.b[2].c` into steps.
pub fn parse_path(path: &str) -> Result<Vec<PathStep>, String> {
    let mut steps = Vec::new();
    if path.trim().is_empty() {
        return Err("the path is empty".to_owned());
    }
    for part in path.split('.') {
        let (key, mut rest) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        if key.is_empty()
            || !key
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        {
            return Err(format!(
                "`{part}` is not a key (letters, digits, `_` and `-`, optionally followed by [index])"
            ));
        }
        steps.push(PathStep::Key(key.to_owned()));
        while !rest.is_empty() {
            let close = rest
                .find(']')
                .ok_or_else(|| format!("unclosed `[` in `{part}`"))?;
            let idx: usize = rest[1..close]
                .parse()
                .map_err(|_| format!("`{}` in `{part}` is not an array index", &rest[1..close]))?;
            steps.push(PathStep::Index(idx));
            rest = &rest[close + 1..];
            if !rest.is_empty() && !rest.starts_with('[') {
                return Err(format!("unexpected `{rest}` after an index in `{part}`"));
            }
        }
    }
    Ok(steps)
}

/// Sets the numeric value at `steps` in `root` (see the module docs for the rules).
pub fn set_path(root: &mut toml::Table, steps: &[PathStep], value: f64) -> Result<(), String> {
    let (last, parents) = steps.split_last().ok_or("the path is empty")?;
    // Work on a copy and put it back at the end, so that errors leave `root` untouched.
    let mut scratch = toml::Value::Table(root.clone());
    let mut cur: &mut toml::Value = &mut scratch;
    let mut walked = String::new();
    for step in parents {
        cur = match step {
            PathStep::Key(k) => {
                walked.push_str(if walked.is_empty() { "" } else { "." });
                walked.push_str(k);
                let table = cur
                    .as_table_mut()
                    .ok_or_else(|| format!("`{walked}`: the parent is not a table"))?;
                table
                    .entry(k.clone())
                    .or_insert_with(|| toml::Value::Table(toml::Table::new()))
            }
            PathStep::Index(i) => {
                walked.push_str(&format!("[{i}]"));
                let arr = cur
                    .as_array_mut()
                    .ok_or_else(|| format!("`{walked}`: not an array"))?;
                let len = arr.len();
                arr.get_mut(*i).ok_or_else(|| {
                    format!("`{walked}`: index out of range (the array has {len} entries)")
                })?
            }
        };
    }
    let slot: &mut toml::Value = match last {
        PathStep::Key(k) => {
            let table = cur
                .as_table_mut()
                .ok_or_else(|| "the parent of the last key is not a table".to_owned())?;
            if k == "reynolds" {
                table.remove("kinematic_viscosity_m2_s");
            } else if k == "kinematic_viscosity_m2_s" {
                table.remove("reynolds");
            }
            table
                .entry(k.clone())
                .or_insert(toml::Value::Float(f64::NAN))
        }
        PathStep::Index(i) => {
            let arr = cur
                .as_array_mut()
                .ok_or_else(|| "the parent of the last index is not an array".to_owned())?;
            let len = arr.len();
            arr.get_mut(*i)
                .ok_or_else(|| format!("index {i} out of range (the array has {len} entries)"))?
        }
    };
    *slot = match slot {
        toml::Value::Float(_) => toml::Value::Float(value),
        toml::Value::Integer(_) => {
            if value.fract() == 0.0 && value.abs() < 9.0e15 {
                toml::Value::Integer(value as i64)
            } else {
                return Err(format!(
                    "the field holds an integer; the level {value} is not an integer"
                ));
            }
        }
        other => {
            return Err(format!(
                "the field holds a {}, not a number",
                other.type_str()
            ));
        }
    };
    let toml::Value::Table(t) = scratch else {
        unreachable!("the root stays a table")
    };
    *root = t;
    Ok(())
}
