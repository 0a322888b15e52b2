//! The SRDF (planning group, solved `group_state`, adjacent-collision pairs) and the joint
//! values as JSON.

use super::links::num;
use super::{ExportError, JointValue, BASE_LINK, GROUP_NAME};
use serde::Serialize;

pub(super) fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&apos;")
}

/// SRDF: the planning group, the solved state, and collisions between touching neighbours off.
pub(super) fn srdf_text(name: &str, tip: &str, values: &[JointValue], n: usize) -> String {
    let name = xml_escape(name);
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\"?>\n");
    s.push_str(&format!("<robot name=\"{name}\">\n"));
    s.push_str(&format!("  <group name=\"{GROUP_NAME}\">\n"));
    s.push_str(&format!(
        "    <chain base_link=\"{BASE_LINK}\" tip_link=\"{tip}\"/>\n"
    ));
    s.push_str("  </group>\n");
    s.push_str(&format!(
        "  <group_state name=\"{name}\" group=\"{GROUP_NAME}\">\n"
    ));
    for v in values {
        s.push_str(&format!(
            "    <joint name=\"{}\" value=\"{}\"/>\n",
            xml_escape(&v.name),
            num(v.value)
        ));
    }
    s.push_str("  </group_state>\n");
    // The backbone of section i touches disk i-1, disk i and the backbone of section i+1 by
    // construction; cable chords (on disk i) touch disk i-1.
    for i in 1..=n {
        let mut pairs = vec![
            (format!("disk_{}", i - 1), format!("section_{i}_chord")),
            (format!("section_{i}_chord"), format!("disk_{i}")),
            (format!("disk_{}", i - 1), format!("disk_{i}")),
        ];
        if i < n {
            pairs.push((
                format!("section_{i}_chord"),
                format!("section_{}_chord", i + 1),
            ));
        }
        for (a, b) in pairs {
            s.push_str(&format!(
                "  <disable_collisions link1=\"{a}\" link2=\"{b}\" reason=\"Adjacent\"/>\n"
            ));
        }
    }
    s.push_str("</robot>\n");
    s
}

#[derive(Serialize)]
pub(super) struct JointsJson<'a> {
    robot: &'a str,
    method: &'a str,
    group: &'a str,
    group_state: &'a str,
    units: &'a str,
    joints: &'a [JointValue],
}

pub(super) fn json_text(
    name: &str,
    method: &str,
    values: &[JointValue],
) -> Result<String, ExportError> {
    serde_json::to_string_pretty(&JointsJson {
        robot: name,
        method,
        group: GROUP_NAME,
        group_state: name,
        units: "rad for revolute joints, m for prismatic (section_*_extension, port_insertion)",
        joints: values,
    })
    .map_err(|e| ExportError::Urdf {
        reason: format!("joint values as JSON: {e}"),
    })
}
