//! The entries of an actuation file (`"actuation": [{"cable": NAME, "shorten": METRES}, …]`),
//! checked before any is used: each an object naming a cable of the model, no cable twice. A
//! name the model does not have (a typo, or a file written for another robot) is refused by
//! name rather than ignored.

use crate::error::ModelError;
use crate::model::Model;
use serde_json::Value;

/// Every entry of `list` names a distinct cable of `model` (`path` for the message).
pub(super) fn entries(list: &[Value], model: &Model, path: &str) -> Result<(), ModelError> {
    let cables = &model.robot.cables;
    let mut seen = vec![false; cables.len()];
    for (k, e) in list.iter().enumerate() {
        let field = format!("actuation[{k}].cable");
        let name = e.get("cable").and_then(|n| n.as_str()).ok_or_else(|| {
            ModelError::invalid(&field, format!("`{path}`: each entry needs a cable name"))
        })?;
        let Some(c) = cables.iter().position(|c| c.name == name) else {
            let known: Vec<&str> = cables.iter().map(|c| c.name.as_str()).collect();
            return Err(ModelError::invalid(
                &field,
                format!(
                    "`{path}` names cable `{}`, which `{}` does not have (its cables: {})",
                    name.escape_debug(),
                    model.robot.name,
                    known.join(", ")
                ),
            ));
        };
        if std::mem::replace(&mut seen[c], true) {
            return Err(ModelError::invalid(
                &field,
                format!("`{path}` gives cable `{name}` twice"),
            ));
        }
    }
    Ok(())
}
