//! Actuation files (`"actuation": [{"cable": NAME, "shorten": METRES, "tension": NEWTONS}, …]`,
//! what `ccrkit reach --json` writes), read into a point of the actuation space, and a model's
//! own actuation as such a point. The entries are checked before any is used: each an object
//! naming a cable of the model, no cable twice. A name the model does not have (a typo, or a
//! file written for another robot) is refused by name rather than ignored. In tension space
//! each cable's value is its entry's `tension` \[N\], else its `shorten` \[m\]; a file that
//! names its `space` (a plan's JSON and a reach answer do) must name the one planned in. A
//! file that names what it was made for (`made_for`, [`MadeFor`]: a reach answer's) is
//! refused by name when read for another robot or another actuation space
//! ([`read_actuation_file`]); a file without it (hand-written, or older) is read by cable name
//! with a warning ([`ActuationFile::warning`]). The file is at most 1 MiB
//! ([`crate::model::read::MAX_ACTUATION_BYTES`]).

use crate::error::ModelError;
use crate::fingerprint::MadeFor;
use crate::model::actuation::{Actuation, Input};
use crate::model::Model;
use crate::reach::Space;
use serde::Deserialize;
use serde_json::Value;

/// Every entry of `list` names a distinct cable of `model` (`path` for the message).
fn entries(list: &[Value], model: &Model, path: &str) -> Result<(), ModelError> {
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

/// The point of the shortening space of a model's actuation ([`actuation_of_in`]).
pub fn actuation_of(model: &Model, act: &Actuation) -> Vec<f64> {
    actuation_of_in(model, act, Input::Shortening)
}

/// The point of the actuation space ([`crate::reach::Space`]) driven by `input` of a model's
/// actuation: each cable's `shorten` \[m\] (its `tension` \[N\] in tension space; 0 where it has
/// none), then, with a port, its insertion and rotation (default: all out, unturned).
pub fn actuation_of_in(model: &Model, act: &Actuation, input: Input) -> Vec<f64> {
    let mut x: Vec<f64> = (0..model.robot.cables.len())
        .map(|c| match input {
            Input::Shortening => act.shortening_length(&model.robot, c),
            Input::Tension => act.cables.get(c).and_then(|d| d.tension),
        })
        .map(|v| v.unwrap_or(0.0))
        .collect();
    if model.robot.port.is_some() {
        x.push(act.insertion.unwrap_or(model.robot.length()));
        x.push(act.rotation.unwrap_or(0.0));
    }
    x
}

/// Read an actuation file of shortenings ([`read_actuation_in`]).
pub fn read_actuation(path: &std::path::Path, model: &Model) -> Result<Vec<f64>, ModelError> {
    read_actuation_in(path, model, Input::Shortening)
}

/// Read an actuation file into a point of the space driven by `input`: JSON with
/// `"actuation": [{"cable": NAME, "shorten": METRES}, …]` (in tension space
/// `{"cable": NAME, "tension": NEWTONS}`) naming every cable of the model, and, for a robot
/// with a port, `"insertion"` \[m\] and `"rotation"` \[rad\] (default: the model's) — what
/// `ccrkit reach --json` and each waypoint of `ccrkit plan --json` write. A file that names
/// what it was made for (`made_for`) must name this model's robot; the space it was made for
/// is checked by [`read_actuation_file`], which has the space. The limits are checked where
/// the point is used (the plan's start and goal, by name).
pub fn read_actuation_in(
    path: &std::path::Path,
    model: &Model,
    input: Input,
) -> Result<Vec<f64>, ModelError> {
    let p = path.display().to_string();
    let v = json(path, input)?;
    if let Some(m) = made_for(&v, &p)? {
        m.check_robot("made_for", &model.robot)
            .map_err(|e| in_file(e, &p))?;
    }
    point(&v, &p, model, input)
}

/// An actuation file read against an actuation space ([`read_actuation_file`]).
#[derive(Debug, Clone)]
pub struct ActuationFile {
    /// The point of the space: each cable's shortening \[m\] (tension \[N\] in tension space),
    /// then, with a port, insertion \[m\] and rotation \[rad\].
    pub point: Vec<f64>,
    /// What the file was made for, checked against the space; `None` for a file without
    /// `made_for` (written by hand, or before ccrkit recorded it), read by cable name only.
    pub made_for: Option<MadeFor>,
}

impl ActuationFile {
    /// The warning a front end prints for a file read unchecked (no `made_for`), naming `path`.
    pub fn warning(&self, path: &std::path::Path) -> Option<String> {
        self.made_for.is_none().then(|| {
            format!(
                "`{}` names no `made_for` (written by hand, or by a ccrkit before it recorded \
                 one): read by cable name, not checked against the robot and actuation space it \
                 was made for",
                path.display()
            )
        })
    }
}

/// Read an actuation file ([`read_actuation_in`]) as a point of `space`: a file that names
/// what it was made for (`made_for`, as `reach --json` writes) is refused by name when it was
/// made for another robot (`made_for.robot_fingerprint`) or another actuation space —
/// shortenings against tensions, other limits or scales (`made_for.space_fingerprint`). A file
/// without `made_for` is read by cable name, with [`ActuationFile::warning`].
pub fn read_actuation_file(
    path: &std::path::Path,
    model: &Model,
    space: &Space,
) -> Result<ActuationFile, ModelError> {
    let p = path.display().to_string();
    let v = json(path, space.input)?;
    let made_for = made_for(&v, &p)?;
    if let Some(m) = &made_for {
        m.check_space("made_for", space)
            .map_err(|e| in_file(e, &p))?;
    }
    let point = point(&v, &p, model, space.input)?;
    Ok(ActuationFile { point, made_for })
}

/// The file's JSON (capped at [`crate::model::read::MAX_ACTUATION_BYTES`]), refused by name
/// when it names a `space` other than `input`'s.
fn json(path: &std::path::Path, input: Input) -> Result<Value, ModelError> {
    let p = path.display().to_string();
    let text = crate::model::read::read_text_capped(
        path,
        crate::model::read::MAX_ACTUATION_BYTES,
        "actuation file",
    )?;
    let v: Value = serde_json::from_str(&text).map_err(|e| ModelError::Parse {
        path: p.clone(),
        reason: e.to_string(),
    })?;
    if let Some(space) = v.get("space") {
        if space.as_str() != Some(input.name()) {
            return Err(ModelError::invalid(
                "space",
                format!(
                    "`{p}` was written in {} space; this request searches {}s ({})",
                    space.as_str().unwrap_or("another"),
                    input.name(),
                    unit(input)
                ),
            ));
        }
    }
    Ok(v)
}

/// The file's `made_for`, if it has one (refused by name when it is not one).
fn made_for(v: &Value, p: &str) -> Result<Option<MadeFor>, ModelError> {
    match v.get("made_for") {
        None => Ok(None),
        Some(m) => MadeFor::deserialize(m).map(Some).map_err(|e| {
            ModelError::invalid("made_for", format!("`{p}`: not what ccrkit writes: {e}"))
        }),
    }
}

/// `e` with the file named in its reason.
fn in_file(e: ModelError, p: &str) -> ModelError {
    match e {
        ModelError::Invalid { field, reason } => {
            ModelError::invalid(field, format!("`{p}` was {reason}"))
        }
        other => other,
    }
}

/// The point the file's entries give, each cable named once ([`entries`]).
fn point(v: &Value, p: &str, model: &Model, input: Input) -> Result<Vec<f64>, ModelError> {
    let list = v
        .get("actuation")
        .and_then(|a| a.as_array())
        .ok_or_else(|| {
            ModelError::invalid("actuation", format!("`{p}` has no `actuation` list"))
        })?;
    entries(list, model, p)?;
    let key = match input {
        Input::Shortening => "shorten",
        Input::Tension => "tension",
    };
    let mut x = model
        .robot
        .cables
        .iter()
        .map(|c| {
            list.iter()
                .find(|e| e.get("cable").and_then(|n| n.as_str()) == Some(c.name.as_str()))
                .and_then(|e| e.get(key).and_then(|s| s.as_f64()))
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    ModelError::invalid(
                        format!("actuation[{}].{key}", c.name),
                        format!(
                            "`{p}` gives no finite {} for cable `{}` ({})",
                            input.name(),
                            c.name,
                            unit(input)
                        ),
                    )
                })
        })
        .collect::<Result<Vec<f64>, ModelError>>()?;
    // With a port: the insertion and rotation beside the cables (default: the model's).
    if model.robot.port.is_some() {
        let here = actuation_of(model, &model.actuation);
        let k = model.robot.cables.len();
        for (i, key) in ["insertion", "rotation"].into_iter().enumerate() {
            let x_i = match v.get(key) {
                None => here[k + i],
                Some(val) => val.as_f64().filter(|x| x.is_finite()).ok_or_else(|| {
                    ModelError::invalid(key, format!("`{p}` gives `{key}` {val}, not a number"))
                })?,
            };
            x.push(x_i);
        }
    }
    Ok(x)
}

fn unit(input: Input) -> &'static str {
    match input {
        Input::Shortening => "m",
        Input::Tension => "N",
    }
}
