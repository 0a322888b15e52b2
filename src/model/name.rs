//! Names (the model's, cables', obstacles'): not empty, and only characters every format they
//! are written to can hold. They go into URDF and SRDF (XML 1.0, whose text may not hold most
//! control characters even escaped, nor U+FFFE/U+FFFF), JSON and CSV; a control character
//! (U+0000–U+001F, U+007F–U+009F, tab and newline included) or a Unicode noncharacter
//! (U+FDD0–U+FDEF, U+nFFFE, U+nFFFF) is refused by name rather than written as a file another
//! tool cannot read.

use crate::error::ModelError;

/// `name` as the value of `field`: refused when empty, or naming the first character it may
/// not hold and where.
pub fn check_name(field: impl Into<String>, name: &str) -> Result<(), ModelError> {
    if name.trim().is_empty() {
        return Err(ModelError::invalid(field, "must not be empty"));
    }
    match name.chars().enumerate().find(|(_, c)| !allowed(*c)) {
        None => Ok(()),
        Some((at, c)) => Err(ModelError::invalid(
            field,
            format!(
                "must not hold the {} U+{:04X} (character {}): names are written into URDF/SRDF \
                 (XML), JSON and CSV",
                if c.is_control() {
                    "control character"
                } else {
                    "noncharacter"
                },
                c as u32,
                at + 1
            ),
        )),
    }
}

/// Whether a name may hold `c`.
fn allowed(c: char) -> bool {
    let u = c as u32;
    !c.is_control() && !(0xFDD0..=0xFDEF).contains(&u) && (u & 0xFFFE) != 0xFFFE
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_and_noncharacters_are_refused_by_name() {
        for (name, says) in [
            ("a\u{1}b", "control character U+0001 (character 2)"),
            ("\0", "control character U+0000"),
            ("x\u{FFFE}", "noncharacter U+FFFE"),
            ("x\u{1FFFF}", "noncharacter U+1FFFF"),
            ("tab\there", "U+0009"),
            ("del\u{7f}", "U+007F"),
            ("c1\u{85}", "U+0085"),
            ("  ", "must not be empty"),
        ] {
            let e = check_name("name", name).expect_err(name);
            assert!(e.to_string().contains(says), "{name:?}: {e}");
        }
        for ok in [
            "paper-case-1",
            "Kabel A",
            "é ü ß",
            "カテーテル",
            "a&b<c>\"'",
            "\u{FFFD}",
        ] {
            check_name("name", ok).expect(ok);
        }
    }
}
