//! A plan's waypoints as a CSV of joint values (`ccrkit plan --trajectory`): the articulated
//! URDF export's joints, so a URDF client replays the path, and in tension space each cable's
//! commanded tension, so a controller replays its inputs.

use super::Plan;
use crate::export::{export_urdf, ExportError, UrdfMode, UrdfOptions};
use crate::model::actuation::Input;
use crate::model::Model;

impl Plan {
    /// The path as joint values of the articulated URDF export (`ccrkit export urdf`, same
    /// joint names), one CSV row per waypoint: `waypoint,<joint>,…`. Through a port the
    /// base joints come first: `port_insertion` (the insertion `d` \[m\]) and
    /// `port_rotation` (the rotation `ψ` \[rad\]), so a URDF client replays them. A plan in
    /// tension space ends each row with the cables' tensions \[N\], one column
    /// `<cable>_tension_n` per cable (named as the workspace study's columns). Fields holding
    /// a comma or a quote are quoted (RFC 4180, by the `csv` crate).
    pub fn trajectory_csv(&self, model: &Model) -> Result<String, ExportError> {
        let opts = UrdfOptions {
            mode: UrdfMode::Articulated,
            cables: false,
            name: None,
        };
        let k = self.cables.len();
        let mut w = csv::WriterBuilder::new().from_writer(Vec::new());
        let mut names: Vec<String> = Vec::new();
        let fail = |e: csv::Error| ExportError::Input {
            field: "trajectory".into(),
            reason: e.to_string(),
        };
        for (i, n) in self.waypoints.iter().enumerate() {
            let e = export_urdf(&n.shape, &model.robot, &opts)?;
            let these: Vec<String> = e.joint_values.iter().map(|j| j.name.clone()).collect();
            if i == 0 {
                let mut head = vec!["waypoint".to_string()];
                head.extend(these.iter().cloned());
                if self.input == Input::Tension {
                    head.extend(self.cables.iter().map(|c| format!("{c}_tension_n")));
                }
                w.write_record(&head).map_err(fail)?;
                names = these;
            } else if these != names {
                // A row must fill the header's columns (a port on some waypoints only).
                return Err(ExportError::Input {
                    field: format!("waypoints[{i}]"),
                    reason: format!("exports joints {these:?}, the first waypoint {names:?}"),
                });
            }
            let mut row = vec![i.to_string()];
            row.extend(e.joint_values.iter().map(|j| format!("{:?}", j.value)));
            if self.input == Input::Tension {
                row.extend(n.u[..k].iter().map(|t| format!("{t:?}")));
            }
            w.write_record(&row).map_err(fail)?;
        }
        let bytes = w.into_inner().map_err(|e| ExportError::Input {
            field: "trajectory".into(),
            reason: e.to_string(),
        })?;
        String::from_utf8(bytes).map_err(|e| ExportError::Input {
            field: "trajectory".into(),
            reason: e.to_string(),
        })
    }
}
