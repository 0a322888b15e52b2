//! Measured data: a CSV of commanded cable displacements per row, optionally with the measured
//! tip and a pattern label (the OpenCR FTDCR files: `timestamp, pattern_label, servo_<id>_mm ×9,
//! tip_x, tip_y, tip_z`).
//!
//! The file is RFC 4180 CSV, read by the `csv` crate: a quoted field (`"rep1_all3, same"`) is
//! one field. Columns are found by name in the header, each named once. The cable columns are, unless named
//! ([`DataOptions::columns`]), every column whose name starts with `servo_`, in file order,
//! mapped to the model's cables in robot order (the FTDCR files list them seg-major, the
//! order of the model files in `models/hardware/`). Displacements and tips are in
//! [`DataOptions::unit`] (mm for the FTDCR files) and converted to metres here, once.

use crate::error::ModelError;
use crate::model::bounds;
use nalgebra::Vector3;
use std::path::Path;

/// Most rows one data file may hold (guards against absurd allocations).
pub const MAX_ROWS: usize = 10_000_000;

/// How to read a data file.
#[derive(Debug, Clone)]
pub struct DataOptions {
    /// Cable columns in robot order (empty: every `servo_*` column in file order).
    pub columns: Vec<String>,
    /// Metres per file unit (0.001 for mm).
    pub unit: f64,
}

impl Default for DataOptions {
    fn default() -> Self {
        DataOptions {
            columns: Vec::new(),
            unit: 1e-3,
        }
    }
}

/// Metres per unit for a unit name (`mm`, `m`).
pub fn unit_scale(name: &str) -> Result<f64, ModelError> {
    match name {
        "mm" => Ok(1e-3),
        "m" => Ok(1.0),
        other => Err(ModelError::invalid(
            "unit",
            format!("`{other}` is not a unit: use `mm` or `m`"),
        )),
    }
}

/// A data file, in metres.
#[derive(Debug, Clone, Default)]
pub struct Dataset {
    /// Names of the cable columns, robot order.
    pub columns: Vec<String>,
    /// Commanded displacement per row and cable \[m\] (positive: pulled).
    pub commands: Vec<Vec<f64>>,
    /// Measured tip per row \[m\], when the file has `tip_x, tip_y, tip_z`.
    pub tips: Option<Vec<Vector3<f64>>>,
    /// `pattern_label` per row, when the file has one.
    pub labels: Option<Vec<String>>,
}

impl Dataset {
    /// Number of rows.
    pub fn len(&self) -> usize {
        self.commands.len()
    }
    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.commands.is_empty()
    }
    /// The rows `idx` (in that order) as a new dataset.
    pub fn select(&self, idx: &[usize]) -> Dataset {
        Dataset {
            columns: self.columns.clone(),
            commands: idx.iter().map(|&i| self.commands[i].clone()).collect(),
            tips: self
                .tips
                .as_ref()
                .map(|t| idx.iter().map(|&i| t[i]).collect()),
            labels: self
                .labels
                .as_ref()
                .map(|l| idx.iter().map(|&i| l[i].clone()).collect()),
        }
    }

    /// Read a CSV file.
    pub fn from_file(path: impl AsRef<Path>, opts: &DataOptions) -> Result<Dataset, ModelError> {
        let path = path.as_ref();
        let text = crate::model::read::read_text(path, "data CSV")?;
        Self::from_csv_str(&text, &path.display().to_string(), opts)
    }

    /// Parse CSV text (`name` is used in errors).
    pub fn from_csv_str(text: &str, name: &str, opts: &DataOptions) -> Result<Dataset, ModelError> {
        if !(opts.unit.is_finite() && opts.unit > 0.0) {
            return Err(ModelError::invalid(
                "unit",
                format!("must be > 0, got {}", opts.unit),
            ));
        }
        // RFC 4180 by the `csv` crate: quoted fields (with commas, quotes, line breaks) are
        // one field; blank lines are skipped; every field trimmed.
        let mut rd = csv::ReaderBuilder::new()
            .has_headers(true)
            .flexible(true)
            .trim(csv::Trim::All)
            .from_reader(text.as_bytes());
        let head = rd
            .headers()
            .map_err(|e| ModelError::invalid(format!("{name}: header"), e.to_string()))?
            .clone();
        let header: Vec<&str> = head.iter().collect();
        if header.iter().all(|h| h.is_empty()) {
            return Err(ModelError::invalid(name, "is empty: no header line"));
        }
        check_header(&header, name)?;
        let find = |c: &str| header.iter().position(|h| *h == c);
        let cols: Vec<usize> = if opts.columns.is_empty() {
            header
                .iter()
                .enumerate()
                .filter(|(_, h)| h.starts_with("servo_"))
                .map(|(i, _)| i)
                .collect()
        } else {
            opts.columns
                .iter()
                .map(|c| {
                    find(c).ok_or_else(|| {
                        ModelError::invalid(
                            "columns",
                            format!("`{c}` is not a column of {name} ({})", header.join(",")),
                        )
                    })
                })
                .collect::<Result<_, _>>()?
        };
        check_named_columns(&opts.columns)?;
        if cols.is_empty() {
            return Err(ModelError::invalid(
                "columns",
                format!("{name} has no `servo_*` column; name the cable columns"),
            ));
        }
        let tip_cols = match (find("tip_x"), find("tip_y"), find("tip_z")) {
            (Some(x), Some(y), Some(z)) => Some([x, y, z]),
            _ => None,
        };
        let label_col = find("pattern_label");
        let mut ds = Dataset {
            columns: cols.iter().map(|&i| header[i].to_string()).collect(),
            tips: tip_cols.map(|_| Vec::new()),
            labels: label_col.map(|_| Vec::new()),
            ..Dataset::default()
        };
        for (r, record) in rd.records().enumerate() {
            if r >= MAX_ROWS {
                return Err(ModelError::invalid(
                    name,
                    format!("has more than {MAX_ROWS} rows"),
                ));
            }
            let record = record
                .map_err(|e| ModelError::invalid(format!("{name} row {}", r + 1), e.to_string()))?;
            let f: Vec<&str> = record.iter().collect();
            if f.len() != header.len() {
                return Err(ModelError::invalid(
                    format!("{name} row {}", r + 1),
                    format!("has {} fields, the header {}", f.len(), header.len()),
                ));
            }
            let num = |i: usize| {
                number(f[i], opts.unit, || {
                    format!("{name} row {} column {}", r + 1, header[i])
                })
            };
            ds.commands
                .push(cols.iter().map(|&i| num(i)).collect::<Result<_, _>>()?);
            if let (Some(t), Some(tc)) = (ds.tips.as_mut(), tip_cols) {
                t.push(Vector3::new(num(tc[0])?, num(tc[1])?, num(tc[2])?));
            }
            if let (Some(l), Some(lc)) = (ds.labels.as_mut(), label_col) {
                l.push(f[lc].to_string());
            }
        }
        if ds.commands.is_empty() {
            return Err(ModelError::invalid(name, "has no data rows"));
        }
        Ok(ds)
    }
}

/// A data field `text` in the data's `unit`, in metres: a finite number within ±1 km
/// ([`bounds::COORDINATE`]; no tip or cable of a robot moves farther, and a tip at `1e308` mm
/// once made the summary's tip errors `inf`). Errors name `field()`.
fn number(text: &str, unit: f64, field: impl Fn() -> String) -> Result<f64, ModelError> {
    let x = text
        .parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| ModelError::invalid(field(), format!("`{text}` is not a finite number")))?;
    let m = x * unit;
    if !bounds::COORDINATE.accepts(m) {
        return Err(ModelError::invalid(
            field(),
            format!(
                "`{text}` is {m:e} m, beyond [{:e}, {:e}] m: no tip or cable of a robot moves \
                 that far",
                bounds::COORDINATE.lo,
                bounds::COORDINATE.hi
            ),
        ));
    }
    Ok(m)
}

/// The pattern family of an FTDCR label: the label without its repetition prefix (`rep1_`),
/// its `_hold` suffix, and a trailing direction (`_dir120`): `all3_same`, `seg0_dir`,
/// `tendon3_id5_pull`, `pair01_opp`.
pub fn family(label: &str) -> String {
    let mut s = label;
    if let Some(i) = s.find('_').filter(|_| s.starts_with("rep")) {
        s = &s[i + 1..];
    }
    let s = s.strip_suffix("_hold").unwrap_or(s);
    match s.rfind("_dir") {
        Some(i) if s[i + 4..].chars().all(|c| c.is_ascii_digit()) => s[..i].to_string(),
        _ => s.to_string(),
    }
}

/// The cable columns named (`--columns`), each a cable's own: a column named twice (two
/// cables read the same displacement, and the column meant for one of them is never read) or
/// a tip column or the label read as a cable is refused by name.
fn check_named_columns(columns: &[String]) -> Result<(), ModelError> {
    for (k, c) in columns.iter().enumerate() {
        if let Some(j) = columns[..k].iter().position(|p| p == c) {
            return Err(ModelError::invalid(
                "columns",
                format!("`{c}` is named twice (cables {} and {})", j + 1, k + 1),
            ));
        }
        if matches!(c.as_str(), "tip_x" | "tip_y" | "tip_z" | "pattern_label") {
            return Err(ModelError::invalid(
                "columns",
                format!("`{c}` is not a cable's column (cable {})", k + 1),
            ));
        }
    }
    Ok(())
}

/// A header names each column once, and gives the tip as all of `tip_x`, `tip_y`, `tip_z` or
/// none of them: a duplicated name (`tip_x` twice, no `tip_y`) once dropped the tip comparison
/// without a word.
fn check_header(header: &[&str], name: &str) -> Result<(), ModelError> {
    for (k, h) in header.iter().enumerate() {
        if header[..k].contains(h) {
            return Err(ModelError::invalid(
                format!("{name}: header"),
                format!(
                    "names the column `{}` twice (columns {} and {})",
                    h.escape_debug(),
                    header[..k].iter().position(|x| x == h).unwrap_or(0) + 1,
                    k + 1
                ),
            ));
        }
    }
    let tips = ["tip_x", "tip_y", "tip_z"];
    let given: Vec<&str> = tips.into_iter().filter(|t| header.contains(t)).collect();
    if !given.is_empty() && given.len() < 3 {
        let missing: Vec<&str> = tips.into_iter().filter(|t| !header.contains(t)).collect();
        return Err(ModelError::invalid(
            format!("{name}: header"),
            format!(
                "has {} but not {}: give all three tip columns or none",
                given.join(", "),
                missing.join(", ")
            ),
        ));
    }
    Ok(())
}
