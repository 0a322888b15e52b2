//! The documentation points only at things that exist, without network access: every relative
//! link and `#anchor` in `README.md`, `ARCHITECTURE.md`, `CONTRIBUTING.md`, `CHANGELOG.md` and
//! `docs/**/*.md` resolves; every `--example X`, `--bench X` and `--test X` they name is a
//! target of this package; every `ccrkit SUBCOMMAND` named in their code is a subcommand of the
//! binary; and the guide's benchmark table is the one `examples/perf_table.rs` wrote (its
//! checksum matches, so an edit by hand fails here).
//!
//! Anchors follow GitHub's rule for heading ids: lower-cased, every character that is not a
//! letter, digit, space, `-` or `_` dropped, spaces turned into `-`, and a repeated id
//! numbered `-1`, `-2`, ….

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The Markdown files the checks cover.
fn doc_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = [
        "README.md",
        "ARCHITECTURE.md",
        "CONTRIBUTING.md",
        "CHANGELOG.md",
    ]
    .iter()
    .map(|f| root().join(f))
    .collect();
    let mut stack = vec![root().join("docs")];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir)
            .expect("docs/ is readable")
            .flatten()
        {
            let p = entry.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|e| e == "md") {
                files.push(p);
            }
        }
    }
    files.sort();
    files
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}

fn rel(path: &Path) -> String {
    path.strip_prefix(root())
        .unwrap_or(path)
        .display()
        .to_string()
}

/// A Markdown text split into prose (code blanked out) and code (fenced blocks and inline
/// spans), line by line, so links are taken from prose and commands from code.
struct Split {
    prose: Vec<String>,
    code: Vec<(usize, String)>,
}

fn split(text: &str) -> Split {
    let mut prose = Vec::new();
    let mut code = Vec::new();
    let mut fence: Option<&str> = None;
    for (n, line) in text.lines().enumerate() {
        let trimmed = line.trim_start();
        if let Some(f) = fence {
            if trimmed.starts_with(f) {
                fence = None;
            } else {
                code.push((n + 1, line.to_string()));
            }
            prose.push(String::new());
            continue;
        }
        if trimmed.starts_with("```") || trimmed.starts_with("~~~") {
            fence = Some(&trimmed[..3]);
            prose.push(String::new());
            continue;
        }
        // Inline code spans (single backticks; the docs use no double-backtick spans).
        let mut p = String::new();
        let mut rest = line;
        while let Some(a) = rest.find('`') {
            p.push_str(&rest[..a]);
            match rest[a + 1..].find('`') {
                Some(b) => {
                    code.push((n + 1, rest[a + 1..a + 1 + b].to_string()));
                    rest = &rest[a + 2 + b..];
                }
                None => {
                    rest = &rest[a..];
                    break;
                }
            }
        }
        p.push_str(rest);
        prose.push(p);
    }
    Split { prose, code }
}

/// GitHub's id of a heading's text.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            '-' | '_' => Some(c),
            c if c.is_alphanumeric() => Some(c),
            _ => None,
        })
        .flat_map(char::to_lowercase)
        .collect()
}

/// The anchors a Markdown file defines (its headings, numbered when repeated).
fn anchors(text: &str) -> BTreeSet<String> {
    let mut seen = BTreeSet::new();
    let mut fence = false;
    for line in text.lines() {
        let t = line.trim_start();
        if t.starts_with("```") || t.starts_with("~~~") {
            fence = !fence;
            continue;
        }
        if fence || !t.starts_with('#') {
            continue;
        }
        let title = t.trim_start_matches('#');
        if !title.starts_with(' ') {
            continue;
        }
        let base = slug(title);
        let mut id = base.clone();
        let mut k = 0;
        while seen.contains(&id) {
            k += 1;
            id = format!("{base}-{k}");
        }
        seen.insert(id);
    }
    seen
}

/// The targets of inline links and images `[text](target)` and of reference definitions
/// `[label]: target` in one line of prose.
fn link_targets(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = line;
    while let Some(i) = rest.find("](") {
        let after = &rest[i + 2..];
        let end = after.find(')').unwrap_or(after.len());
        let target = after[..end].split_whitespace().next().unwrap_or("");
        out.push(target.trim_matches(|c| c == '<' || c == '>').to_string());
        rest = &after[end..];
    }
    let t = line.trim_start();
    if t.starts_with('[') {
        if let Some(i) = t.find("]: ") {
            out.push(
                t[i + 3..]
                    .split_whitespace()
                    .next()
                    .unwrap_or("")
                    .to_string(),
            );
        }
    }
    out
}

#[test]
fn every_relative_link_and_anchor_resolves() {
    let mut bad = Vec::new();
    let mut checked = 0;
    for file in doc_files() {
        let text = read(&file);
        let s = split(&text);
        for (n, line) in s.prose.iter().enumerate() {
            for target in link_targets(line) {
                if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
                    continue;
                }
                checked += 1;
                let (path, anchor) = match target.split_once('#') {
                    Some((p, a)) => (p, Some(a)),
                    None => (target.as_str(), None),
                };
                let dest = if path.is_empty() {
                    file.clone()
                } else {
                    file.parent().expect("a file has a folder").join(path)
                };
                if !dest.exists() {
                    bad.push(format!(
                        "{}:{}: `{target}`: no such file",
                        rel(&file),
                        n + 1
                    ));
                    continue;
                }
                if let Some(a) = anchor {
                    let ids = if dest.is_file() && dest.extension().is_some_and(|e| e == "md") {
                        anchors(&read(&dest))
                    } else {
                        BTreeSet::new()
                    };
                    if !ids.contains(a) {
                        bad.push(format!(
                            "{}:{}: `{target}`: no heading `#{a}`",
                            rel(&file),
                            n + 1
                        ));
                    }
                }
            }
        }
    }
    assert!(
        checked > 50,
        "only {checked} links found: is the parser broken?"
    );
    assert!(bad.is_empty(), "broken links:\n{}", bad.join("\n"));
}

/// Every `FLAG NAME` in the docs' text (`--example paper_cases`).
fn named_after(text: &str, flag: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let mut rest = line;
        while let Some(i) = rest.find(flag) {
            let after = rest[i + flag.len()..].trim_start_matches(['=', ' ']);
            let name: String = after
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_' || *c == '-')
                .collect();
            if !name.is_empty() && name.chars().next().is_some_and(|c| c.is_ascii_lowercase()) {
                out.push((n + 1, name));
            }
            rest = &rest[i + flag.len()..];
        }
    }
    out
}

/// A cargo target `name` under `dir` (`dir/name.rs` or `dir/name/main.rs`).
fn target_exists(dir: &str, name: &str) -> bool {
    let d = root().join(dir);
    d.join(format!("{name}.rs")).is_file() || d.join(name).join("main.rs").is_file()
}

#[test]
fn every_example_bench_and_test_named_exists() {
    let mut bad = Vec::new();
    let mut checked = 0;
    for file in doc_files() {
        let text = read(&file);
        for (flag, dir) in [
            ("--example ", "examples"),
            ("--bench ", "benches"),
            ("--test ", "tests"),
        ] {
            for (n, name) in named_after(&text, flag) {
                checked += 1;
                if !target_exists(dir, &name) {
                    bad.push(format!(
                        "{}:{n}: `{flag}{name}`: no {dir}/{name}.rs",
                        rel(&file)
                    ));
                }
            }
        }
    }
    assert!(
        checked > 10,
        "only {checked} targets named: is the parser broken?"
    );
    assert!(bad.is_empty(), "missing targets:\n{}", bad.join("\n"));
}

/// The subcommands `ccrkit ARGS --help` lists.
fn subcommands(bin: &str, args: &[&str]) -> BTreeSet<String> {
    let out = std::process::Command::new(bin)
        .args(args)
        .arg("--help")
        .output()
        .expect("the binary runs");
    assert!(out.status.success(), "ccrkit {args:?} --help failed");
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    text.lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .collect()
}

#[test]
fn every_subcommand_named_exists() {
    let Some(bin) = option_env!("CARGO_BIN_EXE_ccrkit") else {
        eprintln!("the ccrkit binary is not built in this configuration: subcommands not checked");
        return;
    };
    let top = subcommands(bin, &[]);
    assert!(
        top.contains("solve"),
        "ccrkit --help lists no `solve`: {top:?}"
    );
    let nested: std::collections::BTreeMap<&str, BTreeSet<String>> = top
        .iter()
        .filter(|s| *s != "help")
        .map(|s| (s.as_str(), subcommands(bin, &[s.as_str()])))
        .collect();
    let mut bad = Vec::new();
    let mut checked = 0;
    for file in doc_files() {
        for (n, code) in split(&read(&file)).code {
            let mut rest = code.as_str();
            while let Some(i) = rest.find("ccrkit ") {
                // `ccrkit` as a word or a path's last part (`target/release/ccrkit solve`), not
                // the tail of another name.
                let before = rest[..i].chars().last();
                rest = &rest[i + "ccrkit ".len()..];
                if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '-' || c == '.') {
                    continue;
                }
                let mut words = rest.split_whitespace();
                let Some(sub) = words.next() else { continue };
                if !sub.chars().all(|c| c.is_ascii_lowercase() || c == '-') {
                    continue;
                }
                checked += 1;
                if !top.contains(sub) {
                    bad.push(format!(
                        "{}:{n}: `ccrkit {sub}`: no such subcommand",
                        rel(&file)
                    ));
                    continue;
                }
                let Some(inner) = nested.get(sub).filter(|n| !n.is_empty()) else {
                    continue;
                };
                let next = words.next().unwrap_or("");
                let a_word =
                    !next.is_empty() && next.chars().all(|c| c.is_ascii_lowercase() || c == '-');
                if a_word && !inner.contains(next) {
                    bad.push(format!(
                        "{}:{n}: `ccrkit {sub} {next}`: no such subcommand",
                        rel(&file)
                    ));
                }
            }
        }
    }
    assert!(
        checked > 20,
        "only {checked} subcommands named: is the parser broken?"
    );
    assert!(bad.is_empty(), "unknown subcommands:\n{}", bad.join("\n"));
}

/// FNV-1a, 64 bits, as `examples/perf_table.rs` computes it.
fn fnv1a(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

#[test]
fn the_performance_table_is_the_generated_one() {
    let path = root().join("docs/guide/performance.md");
    let text = read(&path);
    let begin = "<!-- performance-table:begin -->\n";
    let end = "<!-- performance-table:end -->";
    let start = text.find(begin).expect("the begin marker") + begin.len();
    let stop = text[start..].find(end).expect("the end marker") + start;
    let table = &text[start..stop];
    let (body, sum) = table
        .rsplit_once("\n<!-- checksum ")
        .expect("the table ends with its checksum: run `cargo run --release --example perf_table`");
    let sum = sum.trim_end().trim_end_matches("-->").trim();
    assert_eq!(
        sum,
        format!("{:016x}", fnv1a(body)),
        "the table was edited by hand: regenerate it with `cargo run --release --example perf_table`"
    );
    assert!(
        body.contains("| bench | benchmark |"),
        "no table between the markers"
    );
}

#[test]
fn the_link_parser_finds_what_it_should() {
    // The checks above are only as good as these pieces: test them on known input.
    assert_eq!(
        slug("`energy`: the whole robot at once"),
        "energy-the-whole-robot-at-once"
    );
    assert_eq!(slug("Reach and plan"), "reach-and-plan");
    let a = anchors("# A\n## A\n```\n# not a heading\n```\n### B c");
    assert_eq!(a, BTreeSet::from(["a".into(), "a-1".into(), "b-c".into()]));
    assert_eq!(
        link_targets("see [x](a.md#b) and ![p](../p.png \"t\") and `[n](no.md)`"),
        vec!["a.md#b".to_string(), "../p.png".into(), "no.md".into()]
    );
    let s = split("a `ccrkit solve` b [l](x.md)\n```sh\nccrkit view\n```\n");
    assert_eq!(s.prose[0], "a  b [l](x.md)");
    assert_eq!(
        s.code,
        vec![(1, "ccrkit solve".to_string()), (3, "ccrkit view".into())]
    );
    assert_eq!(
        named_after("cargo run --example paper_cases -- x", "--example "),
        vec![(1, "paper_cases".into())]
    );
    assert_eq!(fnv1a(""), 0xcbf2_9ce4_8422_2325);
}
