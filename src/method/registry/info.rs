//! The registry's table: what each method is, takes and models (its [`MethodInfo`]), its
//! settings and its resolution ladder. [`MethodKind`](super::MethodKind) reads it; nothing
//! else spells a method's name.

use super::{LoadSupport, MethodInfo, MethodKind};
use crate::method::settings::{common, Range, SettingInfo};
use crate::model::actuation::Input;

const NO_LOADS: LoadSupport = LoadSupport {
    gravity: false,
    tip_force: false,
    tip_moment: false,
};

const GEOMETRIC_SETTINGS: &[SettingInfo] = &[
    common::max_iterations("40"),
    common::tolerance("1e-12", "constraint residual a candidate must reach [m]"),
    SettingInfo {
        name: "zero-angle",
        values: Range::interval(0.0, 1e-3),
        default: "1e-7",
        help: "an angle at or below this is zero (on a kink) [rad]",
    },
];

const ENERGY_SETTINGS: &[SettingInfo] = &[
    common::control("displacement"),
    SettingInfo {
        name: "sub-arcs",
        values: Range::Count {
            min: 1,
            max: 64,
            note: "≤ 4 with length = chord; or one per section, base first: 1,2,4",
        },
        default: "4",
        help: "constant-strain sub-arcs per section (a list: each section its own)",
    },
    common::LENGTH,
    common::ROUTING,
    common::max_iterations("60"),
    common::tolerance("1e-10", "length and stationarity tolerance [m]"),
    SettingInfo {
        name: "min-stretch",
        values: Range::interval(0.0, 1.0),
        default: "0.5",
        help: "smallest backbone stretch 1 + ε accepted before Infeasible",
    },
    SettingInfo {
        name: "samples-per-sub-arc",
        values: Range::whole(1, 64),
        default: "1",
        help: "backbone samples per sub-arc in the output shape",
    },
    SettingInfo {
        name: "contact-sensitivity",
        values: common::SWITCH,
        default: "off",
        help: "stable and jacobian also with pressing contacts (adds the contact curvature, \
               dear near obstacles: cost in the user's guide, performance)",
    },
    SettingInfo {
        name: "sensitivity",
        values: common::SWITCH,
        default: "on",
        help: "stable and jacobian at all (off: skip their KKT solves; `predict` turns it off)",
    },
    SettingInfo {
        name: "shear",
        values: common::SWITCH,
        default: "off",
        help: "the backbone's shear (GA, the Cosserat rod's continuum; path length, no \
               capstan friction): for soft rods",
    },
];

const ROD_SETTINGS: &[SettingInfo] = &[
    common::control("force"),
    common::ROUTING,
    common::LENGTH,
    SettingInfo {
        name: "rk4-steps",
        values: Range::whole(1, 1000),
        default: "3",
        help: "steps per section before bend refinement (RK4 when shooting, Magnus unloaded)",
    },
    SettingInfo {
        name: "adaptive",
        values: Range::Number {
            lo: 1e-14,
            hi: 1.0,
            off: &["off", "none"],
        },
        default: "off",
        help: "adaptive Dormand–Prince RK45 with this tolerance instead of fixed RK4",
    },
    SettingInfo {
        name: "bend-refine",
        values: Range::Number {
            lo: 0.0,
            hi: 1e6,
            off: &["inf", "off"],
        },
        default: "0.5",
        help: "route bend above which a section gets more RK4 steps",
    },
    common::max_iterations("50"),
    common::tolerance("1e-9", "shooting residual [N]"),
    SettingInfo {
        name: "stability",
        values: Range::Choice(&[("check", 0), ("skip", 1)]),
        default: "check",
        help: "focal-point stability test of the answer; skip: report.stable is None (not \
               checked), one variational pass saved",
    },
    SettingInfo {
        name: "solver",
        values: Range::Choice(&[("auto", 0), ("shooting", 1)]),
        default: "auto",
        help: "auto: strains from the tendons' balance at each point, with no external load \
               one Magnus integration (no shooting), with loads and tensions given shooting on \
               the external moment; shooting: always shoot on the strain rates",
    },
];

const CC_SETTINGS: &[SettingInfo] = &[common::control("displacement")];

// Every rung skips the focal-point stability check: the adaptive rungs have no variational
// pass to run it on (`stable` is None there), so with the check on, the fixed-step rungs
// timed about twice the work of the adaptive ones (case I: 2.80 M instructions with the
// check, 1.42 M without). The chart compares the shape solves alone.
const ROD_RESOLUTIONS: &[(&str, &[(&str, &str)])] = &[
    (
        "rk4 2/section",
        &[
            ("rk4-steps", "2"),
            ("control", "force"),
            ("stability", "skip"),
        ],
    ),
    (
        "rk4 3/section",
        &[
            ("rk4-steps", "3"),
            ("control", "force"),
            ("stability", "skip"),
        ],
    ),
    (
        "rk4 4/section",
        &[
            ("rk4-steps", "4"),
            ("control", "force"),
            ("stability", "skip"),
        ],
    ),
    (
        "rk4 6/section",
        &[
            ("rk4-steps", "6"),
            ("control", "force"),
            ("stability", "skip"),
        ],
    ),
    (
        "rk4 8/section",
        &[
            ("rk4-steps", "8"),
            ("control", "force"),
            ("stability", "skip"),
        ],
    ),
    (
        "rk4 12/section",
        &[
            ("rk4-steps", "12"),
            ("control", "force"),
            ("stability", "skip"),
        ],
    ),
    (
        "rk4 20/section",
        &[
            ("rk4-steps", "20"),
            ("control", "force"),
            ("stability", "skip"),
        ],
    ),
    (
        "adaptive 1e-3",
        &[
            ("adaptive", "1e-3"),
            ("control", "force"),
            ("stability", "skip"),
        ],
    ),
    (
        "adaptive 1e-5",
        &[
            ("adaptive", "1e-5"),
            ("control", "force"),
            ("stability", "skip"),
        ],
    ),
    (
        "adaptive 1e-7",
        &[
            ("adaptive", "1e-7"),
            ("control", "force"),
            ("stability", "skip"),
        ],
    ),
];

const DEFAULT_RESOLUTION: &[(&str, &[(&str, &str)])] = &[("default", &[])];

// The energy model's sub-arcs, coarse to fine (the default, 4, among them).
const ENERGY_RESOLUTIONS: &[(&str, &[(&str, &str)])] = &[
    ("sub-arcs 1", &[("sub-arcs", "1")]),
    ("sub-arcs 2", &[("sub-arcs", "2")]),
    ("sub-arcs 3", &[("sub-arcs", "3")]),
    ("sub-arcs 4", &[("sub-arcs", "4")]),
    ("sub-arcs 6", &[("sub-arcs", "6")]),
    ("sub-arcs 8", &[("sub-arcs", "8")]),
    ("sub-arcs 12", &[("sub-arcs", "12")]),
    ("sub-arcs 16", &[("sub-arcs", "16")]),
];

const BOTH: &[Input] = &[Input::Shortening, Input::Tension];
const SHORTENING: &[Input] = &[Input::Shortening];

/// The two geometric methods share everything but their objective (and so the unit of its
/// contact multipliers).
const fn geometric(
    kind: MethodKind,
    name: &'static str,
    summary: &'static str,
    contact_unit: &'static str,
) -> MethodInfo {
    MethodInfo {
        kind,
        name,
        summary,
        inputs: SHORTENING,
        default_input: Input::Shortening,
        obstacles: true,
        loads: NO_LOADS,
        cable_compliance: false,
        capstan_friction: false,
        bending_stiffening: false,
        tendons_inside: false,
        settings: GEOMETRIC_SETTINGS,
        contact_unit,
        resolutions: DEFAULT_RESOLUTION,
    }
}

/// The two rods share everything but their constitutive law.
const fn rod(kind: MethodKind, name: &'static str, summary: &'static str) -> MethodInfo {
    MethodInfo {
        kind,
        name,
        summary,
        inputs: BOTH,
        default_input: Input::Tension,
        obstacles: true,
        loads: LoadSupport {
            gravity: true,
            tip_force: true,
            tip_moment: true,
        },
        cable_compliance: true,
        capstan_friction: false,
        bending_stiffening: false,
        tendons_inside: true,
        settings: ROD_SETTINGS,
        contact_unit: "N",
        resolutions: ROD_RESOLUTIONS,
    }
}

pub(super) const INFO: [MethodInfo; 6] = [
    geometric(
        MethodKind::Geometric,
        "geometric",
        "the paper's section solver, read literally (sum of angles), certified",
        "rad/m",
    ),
    geometric(
        MethodKind::GeometricSquared,
        "geometric-squared",
        "the same sections minimizing squared angles (a discrete bending energy)",
        "rad²/m",
    ),
    MethodInfo {
        kind: MethodKind::Energy,
        name: "energy",
        summary: "whole robot: constant-strain sub-arcs, elastic energy, pull-only cable lengths",
        inputs: BOTH,
        default_input: Input::Shortening,
        obstacles: true,
        loads: LoadSupport {
            gravity: true,
            tip_force: true,
            tip_moment: false,
        },
        cable_compliance: true,
        capstan_friction: true,
        bending_stiffening: true,
        tendons_inside: true,
        settings: ENERGY_SETTINGS,
        contact_unit: "N",
        resolutions: ENERGY_RESOLUTIONS,
    },
    rod(
        MethodKind::Cosserat,
        "cosserat",
        "Rucker–Webster Cosserat rod with shear and extension, shooting (the reference)",
    ),
    rod(
        MethodKind::Kirchhoff,
        "kirchhoff",
        "the same rod, inextensible and unshearable",
    ),
    MethodInfo {
        kind: MethodKind::ConstantCurvature,
        name: "constant-curvature",
        summary: "closed-form arc for straight, parallel cables tied at the tip",
        inputs: BOTH,
        default_input: Input::Shortening,
        obstacles: false,
        loads: NO_LOADS,
        cable_compliance: false,
        capstan_friction: false,
        bending_stiffening: false,
        tendons_inside: true,
        settings: CC_SETTINGS,
        contact_unit: "",
        resolutions: &[
            ("displacement", &[("control", "displacement")]),
            ("force", &[("control", "force")]),
        ],
    },
];

/// Names in registry order.
pub(in crate::method) const NAMES: [&str; 6] = [
    INFO[0].name,
    INFO[1].name,
    INFO[2].name,
    INFO[3].name,
    INFO[4].name,
    INFO[5].name,
];
