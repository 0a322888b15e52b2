//! Workspace sweeps for the view: the CSV `ccrkit study workspace` writes, read back with the
//! `csv` crate.

use super::ExportError;
use crate::study::{sweep_column_is_numeric, sweep_value};
use serde::Serialize;

/// A sweep read from CSV: tips and the other columns.
#[derive(Debug, Clone, PartialEq)]
pub struct Sweep {
    /// Tip of each solved row \[m\] (rows whose tip is empty, i.e. failed, are left out).
    pub tips: Vec<[f64; 3]>,
    /// Other columns, in file order: name and one value per kept row. A text column (e.g.
    /// `status`) is numbered by first appearance: 0, 1, 2, … (names in `categories`).
    pub columns: Vec<(String, Vec<f64>)>,
    /// For text columns: the category names, in number order.
    pub categories: Vec<(String, Vec<String>)>,
}

#[derive(Debug, Clone, Serialize)]
pub(super) struct CloudDoc {
    pub(super) points: Vec<f64>,
    columns: Vec<ColumnDoc>,
    color_by: String,
}

#[derive(Debug, Clone, Serialize)]
struct ColumnDoc {
    name: String,
    values: Vec<f64>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    categories: Vec<String>,
}

const TIP: [&str; 3] = ["tip_x_m", "tip_y_m", "tip_z_m"];

fn bad(field: impl Into<String>, reason: impl Into<String>) -> ExportError {
    ExportError::Input {
        field: field.into(),
        reason: reason.into(),
    }
}

/// Read a workspace CSV (header `sample,…,tip_x_m,tip_y_m,tip_z_m,…`). Every value is checked
/// by its column's name ([`crate::study::sweep_value`]: each tip coordinate finite and within
/// ±[`crate::shape::MAX_EXTENT`] — a tip at `1e308` m was drawn, and the page's view box with it — the
/// sample, the inputs and the iterations in their ranges, any other number column within
/// ±1e9: a `NaN` or `1e308` there broke the page's colour scale); the error names the line
/// and the column. A row whose tip is empty (a failed sample) is left out; a column is text
/// (numbered by first appearance) when it is not one of the workspace's number columns and
/// one of its values is not a number.
pub fn read_sweep(text: &str) -> Result<Sweep, ExportError> {
    let mut rd = csv::ReaderBuilder::new().from_reader(text.as_bytes());
    let header: Vec<String> = rd
        .headers()
        .map_err(|e| bad("sweep header", e.to_string()))?
        .iter()
        .map(|h| h.trim().to_string())
        .collect();
    let tip_at: Vec<usize> = TIP
        .iter()
        .map(|t| {
            header
                .iter()
                .position(|h| h == t)
                .ok_or_else(|| bad("sweep header", format!("no column `{t}`")))
        })
        .collect::<Result<_, _>>()?;
    let others: Vec<usize> = (0..header.len()).filter(|i| !tip_at.contains(i)).collect();
    let at = |line: usize, i: usize| format!("sweep line {line}, column `{}`", header[i]);
    let mut tips = Vec::new();
    let mut lines = Vec::new();
    let mut raw: Vec<Vec<String>> = vec![Vec::new(); others.len()];
    for (r, rec) in rd.records().enumerate() {
        let line = r + 2;
        let rec = rec.map_err(|e| bad(format!("sweep line {line}"), e.to_string()))?;
        let mut tip = [0.0; 3];
        let mut empty = false;
        for (a, &i) in tip_at.iter().enumerate() {
            let s = rec.get(i).unwrap_or("").trim();
            if s.is_empty() {
                empty = true;
                continue;
            }
            tip[a] = sweep_value(&header[i], s).map_err(|e| bad(at(line, i), e))?;
        }
        if empty {
            continue; // a failed sample: no tip to draw
        }
        tips.push(tip);
        lines.push(line);
        for (col, &i) in raw.iter_mut().zip(&others) {
            col.push(rec.get(i).unwrap_or("").trim().to_string());
        }
    }
    if tips.is_empty() {
        return Err(bad("sweep", "no row with a tip"));
    }
    let mut columns = Vec::new();
    let mut categories = Vec::new();
    for (&i, vals) in others.iter().zip(raw) {
        let name = header[i].clone();
        let numeric =
            sweep_column_is_numeric(&name) || vals.iter().all(|v| v.parse::<f64>().is_ok());
        if numeric {
            let v = vals
                .iter()
                .zip(&lines)
                .map(|(v, &line)| sweep_value(&name, v).map_err(|e| bad(at(line, i), e)))
                .collect::<Result<_, _>>()?;
            columns.push((name, v));
        } else {
            let mut names: Vec<String> = Vec::new();
            let v = vals
                .iter()
                .map(|v| {
                    let k = names.iter().position(|n| n == v).unwrap_or_else(|| {
                        names.push(v.clone());
                        names.len() - 1
                    });
                    k as f64
                })
                .collect();
            categories.push((name.clone(), names));
            columns.push((name, v));
        }
    }
    Ok(Sweep {
        tips,
        columns,
        categories,
    })
}

impl Sweep {
    /// The page's cloud, coloured by `color_by` (default: the first column after `sample`,
    /// the first sampled input in ccrkit's CSV).
    pub(super) fn cloud(&self, color_by: Option<&str>) -> Result<CloudDoc, ExportError> {
        let names: Vec<&str> = self.columns.iter().map(|(n, _)| n.as_str()).collect();
        let pick = match color_by {
            Some(c) => {
                names
                    .iter()
                    .find(|n| **n == c)
                    .ok_or_else(|| ExportError::InvalidOption {
                        option: "color-by".into(),
                        reason: format!("no column `{c}` (columns: {})", names.join(", ")),
                    })?
            }
            None => names
                .iter()
                .find(|n| **n != "sample")
                .or(names.first())
                .unwrap_or(&"tip_z_m"),
        };
        let mut columns: Vec<ColumnDoc> = self
            .columns
            .iter()
            .map(|(n, v)| ColumnDoc {
                name: n.clone(),
                values: v.clone(),
                categories: self
                    .categories
                    .iter()
                    .find(|(c, _)| c == n)
                    .map(|(_, k)| k.clone())
                    .unwrap_or_default(),
            })
            .collect();
        for (a, t) in TIP.iter().enumerate() {
            columns.push(ColumnDoc {
                name: t.to_string(),
                values: self.tips.iter().map(|p| p[a]).collect(),
                categories: Vec::new(),
            });
        }
        Ok(CloudDoc {
            points: self.tips.iter().flatten().copied().map(super::r7).collect(),
            columns,
            color_by: pick.to_string(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_workspace_format_and_skips_failed_rows() {
        let text = "sample,A_shortening_fraction,B_shortening_fraction,tip_x_m,tip_y_m,tip_z_m,status,iterations\n\
0,0.01,0.02,1e-3,2e-3,0.17,converged,5\n\
1,0.03,0.04,,,,failed:infeasible,40\n\
2,0.05,0.06,-1e-3,0,0.16,converged,6\n";
        let s = read_sweep(text).unwrap();
        assert_eq!(s.tips, vec![[1e-3, 2e-3, 0.17], [-1e-3, 0.0, 0.16]]);
        let names: Vec<&str> = s.columns.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            [
                "sample",
                "A_shortening_fraction",
                "B_shortening_fraction",
                "status",
                "iterations"
            ]
        );
        assert_eq!(s.columns[1].1, vec![0.01, 0.05]);
        assert_eq!(
            s.categories,
            vec![("status".to_string(), vec!["converged".to_string()])]
        );
        let c = s.cloud(None).unwrap();
        assert_eq!(c.color_by, "A_shortening_fraction");
        let e = s.cloud(Some("nope")).unwrap_err();
        assert!(e.to_string().contains("color-by"), "{e}");
    }

    #[test]
    fn bad_sweeps_are_named() {
        let e = read_sweep("sample,x\n0,1\n").unwrap_err();
        assert!(e.to_string().contains("tip_x_m"), "{e}");
        let e = read_sweep("tip_x_m,tip_y_m,tip_z_m\n0,abc,1\n").unwrap_err();
        assert!(
            e.to_string().contains("line 2") && e.to_string().contains("tip_y_m"),
            "{e}"
        );
        let e = read_sweep("tip_x_m,tip_y_m,tip_z_m\n,,\n").unwrap_err();
        assert!(e.to_string().contains("no row"), "{e}");
    }
}
