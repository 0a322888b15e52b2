//! A rigorous lower bound on the section objective over one face's whole feasible set, from
//! the constraints one at a time (to skip faces that cannot beat the best
//! certified candidate).
//!
//! # Derivation
//!
//! On a face with zero set `Z` and taut set `T`, every feasible pose has `|p| = l0` and
//! `|p + Q h_j − h′_j| = l_j` for `j ∈ T`. Each objective term `t ∉ Z` is bounded below
//! separately and the bounds are summed (dropping the coupling between terms only lowers the
//! bound). Every bound is the angular distance from a unit direction `u` to a *band* on a
//! sphere: the points `x` with `|x| = R` and `|x − c| ∈ [lo, hi]`. By the law of cosines the
//! angle θ between `x` and `ĉ` is monotone in `|x − c|`,
//! `cos θ = (R² + |c|² − d²) / (2 R |c|)`, so the band is `θ ∈ [θ_lo, θ_hi]` and the angle from
//! `u` to it is `max(0, θ_lo − α, α − θ_hi)` with `α = ang(u, ĉ)`; the band is empty (the
//! face infeasible) when `[lo, hi]` misses `[|R − |c||, R + |c|]`.
//!
//! - Tangent term free, coupler of cable `j` zero: `Q ĥ_j = ĥ_j` so `Q h_j = h_j` and
//!   `p ∈ {|p| = l0, |p − (h′_j − h_j)| = l_j}`; the tangent angle is at least the angle from
//!   `ẑ` to that circle (and the face is infeasible if it is empty: in case I, where the
//!   cables run straight, `h′_j = h_j` and the circle needs `l_j = l0`).
//! - Tangent term zero: `p = l0 ẑ`, so `Q h_j ∈ {|x| = |h_j|, |x − (h′_j − l0 ẑ)| = l_j}`; a free
//!   coupler's angle is at least the angle from `ĥ_j` to that circle; a zero coupler needs
//!   `h_j` on it.
//! - Otherwise (`Q` or `p` free): `p` is on the band `|p − h′_j| ∈ [l_j − |h_j|, l_j + |h_j|]`
//!   and `Q h_j` on `|x − h′_j| ∈ [l_j − l0, l_j + l0]`, weaker bounds of the same kind.
//!
//! Newton's candidates meet the constraints only to the tolerance, so every length is widened
//! by a slack (at least [`LENGTH_SLACK`]); a zero coupler is called off its circle only by more
//! than [`BOUND_MARGIN`], which covers the rounding of `acos` near ±1.
//!
//! # What the search uses it for
//!
//! Only the infinite value: a face proved infeasible is skipped (`faces.rs`), which cannot
//! change the answer since no run on it converges, so none yields a candidate or an escape.
//! A finite bound above the best candidate so far would prune more (measured: 14 %
//! of case III's iterations), but a skipped face's runs would also skip their escapes, which
//! land on the face with no term at zero — its bound is 0, it contains every pose — so that
//! skip could lose a candidate and is not made.

use super::problem::SectionData;
use nalgebra::Vector3;

/// Each cable length is widened by at least this on either side \[m\] (the search uses
/// 1000× the Newton tolerance when that is larger): 1000× the default tolerance (`1e-12` m),
/// so candidates that meet the constraints only to it stay inside the bands.
pub(super) const LENGTH_SLACK: f64 = 1e-9;

/// A zero coupler's direction must miss its circle by more than this \[rad\] for the face to be
/// called infeasible: `acos` of a cosine rounded by 1e-16 near ±1 errs by up to ~1.5e-8 rad.
pub(super) const BOUND_MARGIN: f64 = 1e-6;

#[cfg(test)]
thread_local! {
    /// Test-only: turn the infeasible-face skip off on this thread, so a test can compare the
    /// search's answer with and without it (not a setting: the skip never changes an answer).
    pub(super) static SKIP_OFF: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Whether the search may skip faces [`SectionData::face_lower_bound`] proves infeasible:
/// always, except in tests that turn it off ([`SKIP_OFF`]) to compare answers.
#[inline]
pub(super) fn skip_enabled() -> bool {
    #[cfg(test)]
    {
        !SKIP_OFF.with(std::cell::Cell::get)
    }
    #[cfg(not(test))]
    {
        true
    }
}

/// Angle from unit `u` to the band `{|x| = r, |x − c| ∈ [lo, hi]}`; `None` when the band is
/// empty.
pub(super) fn band_angle(
    u: &Vector3<f64>,
    r: f64,
    c: &Vector3<f64>,
    lo: f64,
    hi: f64,
) -> Option<f64> {
    let d = c.norm();
    let (dmin, dmax) = ((r - d).abs(), r + d);
    if hi < dmin || lo > dmax {
        return None;
    }
    if d <= 1e-15 * r.max(1e-300) {
        // Every point of the sphere is at distance r from c: no direction is ruled out.
        return Some(0.0);
    }
    let theta = |dist: f64| {
        let cos = (r * r + d * d - dist * dist) / (2.0 * r * d);
        cos.clamp(-1.0, 1.0).acos()
    };
    let (t_lo, t_hi) = (theta(lo.max(dmin)), theta(hi.min(dmax)));
    let alpha = u.cross(c).norm().atan2(u.dot(c));
    Some((t_lo - alpha).max(alpha - t_hi).max(0.0))
}

impl SectionData {
    /// Lower bound on the literal objective over face `face`'s feasible set with the taut set
    /// `taut`, every length widened by `slack` either side (see the module docs); `+∞` when
    /// the bounds prove the face infeasible.
    pub(super) fn face_lower_bound(&self, face: u32, taut: &[usize], slack: f64) -> f64 {
        let fixed_rotation = self.rotation_fixed(face);
        let zero = |t: usize| face & (1 << t) != 0 || (fixed_rotation && t > 0);
        let tangent_zero = zero(0);
        let z = Vector3::z();
        let mut per_term = vec![0.0f64; self.terms.len()];
        for &j in taut {
            let k = &self.cons[j];
            let (lo, hi) = (k.length - slack, k.length + slack);
            let coupler_zero = zero(k.coupler);
            let hn = k.h.norm();
            if hn == 0.0 {
                continue;
            }
            // ang(ĥ, Qĥ) = ang(−ĥ, −Qĥ): this cable's own hole direction bounds its term.
            let hdir = k.h / hn;
            if tangent_zero {
                let c = k.h_prev - self.l0 * z;
                let Some(a) = band_angle(&hdir, hn, &c, lo, hi) else {
                    return f64::INFINITY;
                };
                if coupler_zero {
                    if a > BOUND_MARGIN {
                        return f64::INFINITY;
                    }
                } else {
                    per_term[k.coupler] = per_term[k.coupler].max(a);
                }
            } else if coupler_zero {
                let Some(a) = band_angle(&z, self.l0, &(k.h_prev - k.h), lo, hi) else {
                    return f64::INFINITY;
                };
                per_term[0] = per_term[0].max(a);
            } else {
                let Some(a) = band_angle(&z, self.l0, &k.h_prev, lo - hn, hi + hn) else {
                    return f64::INFINITY;
                };
                per_term[0] = per_term[0].max(a);
                let Some(b) = band_angle(&hdir, hn, &k.h_prev, lo - self.l0, hi + self.l0) else {
                    return f64::INFINITY;
                };
                per_term[k.coupler] = per_term[k.coupler].max(b);
            }
        }
        self.terms
            .iter()
            .enumerate()
            .filter(|(t, _)| !zero(*t))
            .map(|(t, term)| term.weight * per_term[t])
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::super::problem::SectionData;
    use super::super::Geometric;
    use super::{band_angle, LENGTH_SLACK, SKIP_OFF};
    use crate::model::Model;
    use nalgebra::Vector3;

    /// A deterministic xorshift stream in [0, 1).
    fn stream(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed.wrapping_mul(0x9E3779B97F4A7C15) | 1;
        move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// The closed-form band angle against brute force: 200 000 points spread over the sphere,
    /// those inside the band, their smallest angle from `u`. The closed form never exceeds the
    /// sampled minimum and, where the band holds ≥ 500 samples, is within the sampling
    /// resolution of it; a band called empty has no sample inside.
    #[test]
    fn band_angle_equals_sampled_minimum() {
        let mut rnd = stream(7);
        let n = 200_000;
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        let sphere: Vec<Vector3<f64>> = (0..n)
            .map(|k| {
                let z = 1.0 - 2.0 * (k as f64 + 0.5) / n as f64;
                let s = (1.0 - z * z).sqrt();
                let a = golden * k as f64;
                Vector3::new(s * a.cos(), s * a.sin(), z)
            })
            .collect();
        let (mut empty, mut checked) = (0, 0);
        for _ in 0..300 {
            let mut v = || Vector3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5);
            let u = v().normalize();
            let c = v() * 0.04;
            let r = 0.005 + 0.02 * rnd();
            let mid = 0.03 * rnd();
            let width = 0.0005 + 0.004 * rnd();
            let (lo, hi) = (mid - width, mid + width);
            let inside: Vec<f64> = sphere
                .iter()
                .filter(|x| {
                    let d = (*x * r - c).norm();
                    d >= lo && d <= hi
                })
                .map(|x| u.cross(x).norm().atan2(u.dot(x)))
                .collect();
            match band_angle(&u, r, &c, lo, hi) {
                None => {
                    empty += 1;
                    assert!(inside.is_empty(), "band called empty has a point");
                }
                Some(a) => {
                    let Some(m) = inside.iter().copied().reduce(f64::min) else {
                        continue;
                    };
                    assert!(a <= m + 1e-12, "bound {a} above the sampled minimum {m}");
                    // Where the band holds enough samples, the closed form is its minimum to
                    // within the sampling resolution (~0.008 rad between neighbours).
                    if inside.len() >= 500 {
                        checked += 1;
                        assert!(a >= m - 0.02, "bound {a} far below the sampled minimum {m}");
                    }
                }
            }
        }
        assert!(
            empty > 10 && checked > 100,
            "{empty} empty, {checked} checked"
        );
    }

    /// A random 6-section robot (1–4 cables, straight or helical, shortened −3..6 %).
    fn random_robot(seed: u64) -> String {
        let mut rnd = stream(seed);
        let mut t = String::from(
            "name = \"r\"\n[robot]\nsections = 6\nsection_length = 0.02\ndisk_radius = 0.012\ndisk_thickness = 0.002\nbackbone = { youngs_modulus = 1.1e9, poisson_ratio = 0.3, diameter = 0.003 }\n",
        );
        for k in 0..1 + (rnd() * 4.0) as usize {
            let per_disk = if rnd() < 0.5 { 0.0 } else { -0.6 + 1.2 * rnd() };
            t += &format!(
                "[[cables]]\nname = \"c{k}\"\nradius = {}\nangles = {{ helix = {{ start = {}, per_disk = {per_disk} }} }}\nshorten_percent = {}\n",
                0.004 + 0.006 * rnd(),
                rnd() * std::f64::consts::TAU,
                -3.0 + 9.0 * rnd()
            );
        }
        t
    }

    /// The bound is below every certified candidate Newton finds on its face, and no Newton
    /// run converges on a face it proves infeasible: the paper cases and 300 random robots,
    /// every section, the taut sets "all cables" and each cable alone, every face, every start.
    #[test]
    fn bound_below_every_certified_candidate() {
        let geo = Geometric::literal();
        let mut models: Vec<Model> = (1..=3)
            .map(|c| Model::from_file(format!("models/paper/case{c}.toml")).expect("case"))
            .collect();
        models.extend((0..300).map(|k| Model::from_toml_str(&random_robot(k)).expect("robot")));
        let (mut candidates, mut infeasible, mut positive) = (0, 0, 0);
        for m in &models {
            let frac: Vec<Option<f64>> = (0..m.robot.cables.len())
                .map(|c| m.actuation.shortening_fraction(&m.robot, c))
                .collect();
            for i in 1..=m.robot.sections() {
                let Ok(data) = SectionData::new(&m.robot, &frac, i) else {
                    continue;
                };
                let n = data.cons.len().min(5 - usize::from(data.gauge.is_some()));
                let mut sets: Vec<Vec<usize>> = (0..data.cons.len()).map(|j| vec![j]).collect();
                sets.push((0..n).collect());
                let mut it = 0;
                let starts = geo.starts(&data, None, &mut it);
                for taut in &sets {
                    let fixed = 1 + taut.len() + usize::from(data.gauge.is_some());
                    for face in data.faces(fixed, taut) {
                        let lb = data.face_lower_bound(face, taut, LENGTH_SLACK);
                        infeasible += usize::from(lb.is_infinite());
                        positive += usize::from(lb.is_finite() && lb > 0.0);
                        for s in &starts {
                            if let Ok((c, _)) = geo.newton(&data, s, face, taut, false) {
                                candidates += 1;
                                assert!(
                                    c.objective >= lb - 1e-9,
                                    "section {i} face {face}: candidate {} below bound {lb}",
                                    c.objective
                                );
                            }
                        }
                    }
                }
            }
        }
        assert!(
            candidates > 1000 && infeasible > 100 && positive > 100,
            "{candidates} candidates, {infeasible} faces proved infeasible, {positive} positive bounds"
        );
    }

    /// A random 2–6-section robot built to put faces at the edge of feasibility: cables with
    /// coinciding holes (one constraint, the other always slack), holes on one line through
    /// the centre (one coupler term), straight or barely twisted (`per_disk` 1e-10) or helical.
    fn edge_robot(rnd: &mut impl FnMut() -> f64) -> String {
        let mut t = format!(
            "name = \"e\"\n[robot]\nsections = {}\nsection_length = 0.02\ndisk_radius = 0.012\ndisk_thickness = 0.002\nbackbone = {{ youngs_modulus = 1.1e9, poisson_ratio = 0.3, diameter = 0.003 }}\n",
            2 + (rnd() * 5.0) as usize
        );
        let mut prev = (0.006, 0.0, 0.0);
        for k in 0..1 + (rnd() * 4.0) as usize {
            let kind = rnd();
            let (radius, start, per_disk) = if k > 0 && kind < 0.25 {
                prev // coinciding holes
            } else if k > 0 && kind < 0.45 {
                (prev.0, prev.1 + std::f64::consts::PI, prev.2) // collinear, opposite
            } else {
                let per_disk = match (rnd() * 3.0) as usize {
                    0 => 0.0,
                    1 => 1e-10,
                    _ => -0.6 + 1.2 * rnd(),
                };
                (
                    0.004 + 0.006 * rnd(),
                    rnd() * std::f64::consts::TAU,
                    per_disk,
                )
            };
            prev = (radius, start, per_disk);
            t += &format!(
                "[[cables]]\nname = \"c{k}\"\nradius = {radius}\nangles = {{ helix = {{ start = {start}, per_disk = {per_disk} }} }}\nshorten_percent = 0\n"
            );
        }
        t
    }

    /// Sets every constraint's length of `data` at or just off an edge: the undeformed chord
    /// exactly (unshortened), the chord ± 10^U(−12, −6) m, the shortest chord any pose allows
    /// (`l0 − |h| − |h_prev|`) + 10^U(−12, −6) m, or an ordinary 0–3 % shortening.
    fn put_on_edges(data: &mut SectionData, rnd: &mut impl FnMut() -> f64) {
        let l0 = data.l0;
        for k in &mut data.cons {
            let chord0 = k.length; // built unshortened
            let tiny = 10f64.powf(-12.0 + 6.0 * rnd());
            k.length = match (rnd() * 5.0) as usize {
                0 => chord0,
                1 => chord0 + tiny,
                2 => chord0 - tiny,
                3 => l0 - k.h.norm() - k.h_prev.norm() + tiny,
                _ => chord0 * (1.0 - 0.03 * rnd()),
            };
            k.unshortened = (k.length - chord0).abs() <= super::super::problem::UNSHORTENED_TOL;
        }
    }

    /// The skip of faces proved infeasible never changes a section's answer: 400 robots whose
    /// constraints sit at or within 1e-12..1e-6 m of an edge (see [`put_on_edges`]), every
    /// section solved with the skip and without it: the same pose, objective, slack set and
    /// zero terms to the bit, or the same kind of error.
    #[test]
    fn skip_never_changes_the_answer() {
        let geo = Geometric::literal();
        let mut rnd = stream(16);
        let (mut sections, mut solved, mut skipped) = (0, 0, 0);
        for _ in 0..400 {
            let m = Model::from_toml_str(&edge_robot(&mut rnd)).expect("robot");
            let frac: Vec<Option<f64>> = vec![Some(0.0); m.robot.cables.len()];
            for i in 1..=m.robot.sections() {
                let Ok(mut data) = SectionData::new(&m.robot, &frac, i) else {
                    continue;
                };
                put_on_edges(&mut data, &mut rnd);
                let all: Vec<usize> = (0..data.cons.len()).collect();
                let fixed = 1 + all.len() + usize::from(data.gauge.is_some());
                skipped += data
                    .faces(fixed, &all)
                    .iter()
                    .filter(|&&f| data.face_lower_bound(f, &all, LENGTH_SLACK).is_infinite())
                    .count();
                let with = geo.solve_section(&data, i, None, None);
                SKIP_OFF.with(|s| s.set(true));
                let without = geo.solve_section(&data, i, None, None);
                SKIP_OFF.with(|s| s.set(false));
                sections += 1;
                match (&with, &without) {
                    (Ok(a), Ok(b)) => {
                        solved += 1;
                        let same = a.pose.p == b.pose.p
                            && a.pose.q == b.pose.q
                            && a.report.objective.to_bits() == b.report.objective.to_bits()
                            && a.slack == b.slack
                            && a.report.zero_terms == b.report.zero_terms;
                        assert!(
                            same,
                            "section {i}: with the skip {:?} {} {:?}, without {:?} {} {:?}\n{:?}",
                            a.pose.p,
                            a.report.objective,
                            a.slack,
                            b.pose.p,
                            b.report.objective,
                            b.slack,
                            data.cons.iter().map(|k| k.length).collect::<Vec<_>>()
                        );
                    }
                    (Err(a), Err(b)) => assert_eq!(
                        std::mem::discriminant(a),
                        std::mem::discriminant(b),
                        "section {i}: {a} against {b}"
                    ),
                    _ => panic!(
                        "section {i}: with the skip {:?}, without {:?}\n{:?}",
                        with.as_ref().map(|s| s.pose.p).err(),
                        without.as_ref().map(|s| s.pose.p).err(),
                        data.cons.iter().map(|k| k.length).collect::<Vec<_>>()
                    ),
                }
            }
        }
        eprintln!("{sections} sections, {solved} solved, {skipped} faces skipped");
        assert!(
            sections > 1000 && solved > 500 && skipped > 500,
            "{sections} sections, {solved} solved, {skipped} faces skipped"
        );
    }
}
