//! The documentation tested like code: README.md, ARCHITECTURE.md and every docs/**/*.md.
//!
//! - Every relative link and image target exists, and an `#anchor` into a Markdown file
//!   names one of its headings by GitHub's slug rules (lower case, punctuation dropped,
//!   each space a `-`, `-1`, `-2`, ... for a repeated heading).
//! - A fenced block whose info string is `sh runnable` runs with `bash -e` in a fresh
//!   temporary folder that has the repository's `scripts/` linked into it (`sh runnable
//!   root`: in the repository's root), with `luamotion` on the PATH: the binary under test,
//!   given a namespace of the block's own (a block's `--ns NAME` is made the block's own
//!   too) and `XDG_STATE_HOME` in the temporary folder. It must exit 0 within
//!   `SH_DEADLINE`.
//! - A fenced block whose info string is `lua runnable` is a whole program, run by
//!   `luamotion test` on the built-in machine on the simulation clock; it must pass.
//!   (Once `luamotion check` exists, issue 40, the Lua blocks go through it as well.)
//!
//! Blocks without `runnable` are shown, never run. docs/guide/README.md says the same for
//! the docs' writers. Every failure names its file and line; all of them are reported at once.

mod common;

use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{BIN, kill_all, repo_path, unique_ns};

/// How long one `sh runnable` block may take.
const SH_DEADLINE: Duration = Duration::from_secs(60);
/// How long one `lua runnable` block may run under `luamotion test` (its `--timeout`, s).
const LUA_DEADLINE_S: u64 = 60;
/// The commands that take `--ns`: a block's controllers and tools get a namespace of its own.
const NAMESPACED: &str = "run|serve|tasks|events|scope";

/// A fenced code block: where it starts (the fence's line), its info string and its text.
#[derive(Debug)]
struct Block {
    line: usize,
    info: Vec<String>,
    text: String,
}

impl Block {
    fn runnable(&self) -> bool {
        self.info.iter().any(|w| w == "runnable")
    }

    fn language(&self) -> &str {
        self.info.first().map_or("", String::as_str)
    }
}

/// A link or image target outside code: `[text](target)`, `![alt](target)`, `[ref]: target`.
#[derive(Debug)]
struct Link {
    line: usize,
    target: String,
}

/// What the checks need of one Markdown file.
#[derive(Debug, Default)]
struct Markdown {
    blocks: Vec<Block>,
    links: Vec<Link>,
    /// The anchors of its headings, as GitHub makes them.
    anchors: Vec<String>,
}

impl Markdown {
    fn parse(text: &str) -> Markdown {
        let mut doc = Markdown::default();
        let mut fence: Option<(char, usize, Block)> = None;
        for (index, line) in text.lines().enumerate() {
            let number = index + 1;
            let trimmed = line.trim_start();
            let marker = trimmed.chars().next().filter(|c| *c == '`' || *c == '~');
            let run = marker.map_or(0, |c| trimmed.chars().take_while(|&x| x == c).count());
            let closes = fence
                .as_ref()
                .is_some_and(|(c, len, _)| marker == Some(*c) && run >= *len && trimmed[run..].trim().is_empty());
            match &mut fence {
                Some(_) if closes => {
                    let (_, _, block) = fence.take().expect("an open fence");
                    doc.blocks.push(block);
                }
                Some((_, _, block)) => {
                    block.text.push_str(line);
                    block.text.push('\n');
                }
                None if run >= 3 => {
                    let info = trimmed[run..].split_whitespace().map(str::to_string).collect();
                    fence =
                        Some((marker.expect("a fence marker"), run, Block { line: number, info, text: String::new() }));
                }
                None => {
                    if let Some(heading) = heading_text(line) {
                        let slug = slug(&heading);
                        let repeated = doc.anchors.iter().filter(|a| a.as_str() == slug || is_repeat(a, &slug)).count();
                        doc.anchors.push(if repeated == 0 { slug } else { format!("{slug}-{repeated}") });
                    }
                    doc.links.extend(link_targets(line).into_iter().map(|target| Link { line: number, target }));
                }
            }
        }
        doc
    }
}

/// `slug-N`, the anchor of a repeat of the heading whose anchor is `slug`.
fn is_repeat(anchor: &str, slug: &str) -> bool {
    anchor.strip_prefix(slug).and_then(|r| r.strip_prefix('-')).is_some_and(|n| n.parse::<u32>().is_ok())
}

/// The text of an ATX heading (`## Text ##`), its links reduced to their text.
fn heading_text(line: &str) -> Option<String> {
    let hashes = line.chars().take_while(|&c| c == '#').count();
    let rest = line.get(hashes..)?;
    if !(1..=6).contains(&hashes) || !(rest.is_empty() || rest.starts_with(' ')) {
        return None;
    }
    let text = rest.trim().trim_end_matches('#').trim_end();
    let mut plain = String::new();
    let mut chars = text.char_indices().peekable();
    while let Some((at, c)) = chars.next() {
        // `[label](target)` shows as `label`.
        if c == ']' && text[at + 1..].starts_with('(') {
            for (_, c) in chars.by_ref() {
                if c == ')' {
                    break;
                }
            }
        } else {
            plain.push(c);
        }
    }
    Some(plain)
}

/// GitHub's heading anchor: lower case; letters, digits, `-`, `_` and spaces kept, the
/// rest dropped; every space a `-`.
fn slug(heading: &str) -> String {
    heading
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | ' '))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The targets a line links to, outside its code spans.
fn link_targets(line: &str) -> Vec<String> {
    let prose = without_code_spans(line);
    let mut targets = Vec::new();
    if let Some(rest) = prose.trim_start().strip_prefix('[')
        && let Some((label, target)) = rest.split_once("]:")
        && !label.is_empty()
        && !label.contains(']')
    {
        targets.extend(target.split_whitespace().next().map(str::to_string));
    }
    let mut from = 0;
    while let Some(at) = prose[from..].find("](") {
        let start = from + at + 2;
        let Some(len) = prose[start..].find(')') else { break };
        let inside = prose[start..start + len].trim();
        let target = inside.trim_start_matches('<').split(['>', ' ']).next().unwrap_or_default();
        if !target.is_empty() {
            targets.push(target.to_string());
        }
        from = start + len;
    }
    targets
}

/// The line with its inline code (`` `x` ``, ``` ``x`` ```) left out.
fn without_code_spans(line: &str) -> String {
    let mut out = String::new();
    let mut rest = line;
    while let Some(open) = rest.find('`') {
        out.push_str(&rest[..open]);
        let ticks = rest[open..].chars().take_while(|&c| c == '`').count();
        let after = &rest[open + ticks..];
        match after.find(&"`".repeat(ticks)) {
            Some(close) => rest = &after[close + ticks..],
            None => return out + &rest[open..],
        }
    }
    out + rest
}

/// README.md, ARCHITECTURE.md and every docs/**/*.md, as paths relative to the repository.
fn documents() -> Vec<PathBuf> {
    let mut files = vec![PathBuf::from("README.md"), PathBuf::from("ARCHITECTURE.md")];
    let mut folders = vec![PathBuf::from("docs")];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(repo_path(folder.to_str().expect("a UTF-8 path"))).expect("docs/").flatten() {
            let relative = folder.join(entry.file_name());
            if entry.path().is_dir() {
                folders.push(relative);
            } else if relative.extension().is_some_and(|e| e == "md") {
                files.push(relative);
            }
        }
    }
    files.sort();
    files
}

fn read(relative: &Path) -> Markdown {
    let text = std::fs::read_to_string(repo_path(relative.to_str().expect("a UTF-8 path")))
        .unwrap_or_else(|e| panic!("{}: {e}", relative.display()));
    Markdown::parse(&text)
}

/// What is wrong with the links of `doc` (the file `relative` inside `root`), each with
/// its `file:line`.
fn broken_links(root: &Path, relative: &Path, doc: &Markdown) -> Vec<String> {
    let folder = relative.parent().unwrap_or(Path::new(""));
    let mut broken = Vec::new();
    for link in &doc.links {
        if link.target.contains("://") || link.target.starts_with("mailto:") {
            continue;
        }
        let (path, anchor) = match link.target.split_once('#') {
            Some((path, anchor)) => (path, Some(anchor)),
            None => (link.target.as_str(), None),
        };
        let at = format!("{}:{}", relative.display(), link.line);
        let file = if path.is_empty() { root.join(relative) } else { root.join(folder).join(path) };
        if !file.exists() {
            broken.push(format!("{at}: {} does not exist", link.target));
            continue;
        }
        let Some(anchor) = anchor else { continue };
        if file.extension().is_none_or(|e| e != "md") {
            continue;
        }
        let target = if path.is_empty() {
            None
        } else {
            Some(Markdown::parse(&std::fs::read_to_string(&file).expect("the linked file")))
        };
        let anchors = &target.as_ref().unwrap_or(doc).anchors;
        if !anchors.iter().any(|a| a == anchor) {
            broken.push(format!("{at}: {} names no heading of {}", link.target, file.display()));
        }
    }
    broken
}

/// The `luamotion` a block calls: the binary under test with the block's namespace.
fn luamotion_on_path(bin_dir: &Path, ns: &str) {
    let wrapper = format!(
        r#"#!/usr/bin/env bash
# The binary under test; its controllers and tools in namespace {ns} (tests/docs.rs).
case "$1" in {NAMESPACED}) ;; *) exec {BIN} "$@" ;; esac
args=("$1"); shift; named=
while (($#)); do
  case "$1" in
    --ns) args+=(--ns "{ns}-$2"); shift 2; named=1 ;;
    --ns=*) args+=(--ns "{ns}-${{1#--ns=}}"); shift; named=1 ;;
    *) args+=("$1"); shift ;;
  esac
done
[ -n "$named" ] || args=("${{args[0]}}" --ns {ns} "${{args[@]:1}}")
exec {BIN} "${{args[@]}}"
"#
    );
    std::fs::create_dir_all(bin_dir).expect("the block's bin folder");
    let path = bin_dir.join("luamotion");
    std::fs::write(&path, wrapper).expect("the luamotion wrapper");
    let mut permissions = std::fs::metadata(&path).unwrap().permissions();
    std::os::unix::fs::PermissionsExt::set_mode(&mut permissions, 0o755);
    std::fs::set_permissions(&path, permissions).expect("an executable wrapper");
}

/// Runs one `sh runnable` block of `relative` (read from `root`); what went wrong, if anything.
fn run_sh(root: &Path, relative: &Path, block: &Block) -> Option<String> {
    let at = format!("{}:{}", relative.display(), block.line);
    let dir = tempfile::Builder::new().prefix("docs-block-").tempdir().expect("a temp dir");
    luamotion_on_path(&dir.path().join("bin"), &unique_ns("doc"));
    let work = dir.path().join("work");
    std::fs::create_dir(&work).expect("the block's folder");
    std::os::unix::fs::symlink(root.join("scripts"), work.join("scripts")).expect("scripts/ linked in");
    let cwd = if block.info.iter().any(|w| w == "root") { root.to_path_buf() } else { work };
    let script = dir.path().join("block.sh");
    std::fs::write(&script, &block.text).expect("the block's script");
    let (out, err) = (dir.path().join("stdout"), dir.path().join("stderr"));
    let path = format!("{}:{}", dir.path().join("bin").display(), std::env::var("PATH").unwrap_or_default());
    let mut child = Command::new("bash")
        .arg("-e")
        .arg(&script)
        .current_dir(&cwd)
        .env("PATH", path)
        .env("XDG_STATE_HOME", dir.path().join("state"))
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out).expect("stdout file"))
        .stderr(std::fs::File::create(&err).expect("stderr file"))
        .process_group(0)
        .spawn()
        .expect("bash");
    let deadline = Instant::now() + SH_DEADLINE;
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break Some(status);
        }
        if Instant::now() > deadline {
            kill_all(&mut child);
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let output = || {
        let text = |p: &Path| std::fs::read_to_string(p).unwrap_or_default();
        format!("stdout:\n{}stderr:\n{}", text(&out), text(&err))
    };
    match status {
        Some(status) if status.success() => None,
        Some(status) => Some(format!("{at}: the sh block failed ({status})\n{}{}", block.text, output())),
        None => Some(format!("{at}: the sh block ran longer than {SH_DEADLINE:?}\n{}{}", block.text, output())),
    }
}

/// Runs `lua runnable` blocks, (`file:line`, program) each, with one `luamotion test`;
/// what went wrong with each that did not pass.
fn run_lua(blocks: &[(String, &str)]) -> Vec<String> {
    let dir = tempfile::Builder::new().prefix("docs-lua-").tempdir().expect("a temp dir");
    let files: Vec<PathBuf> = blocks
        .iter()
        .map(|(at, program)| {
            let path = dir.path().join(format!("{}.lua", at.replace(['/', ':'], "_")));
            std::fs::write(&path, program).expect("the block's program");
            path
        })
        .collect();
    let child = Command::new(BIN)
        .arg("test")
        .args(["--timeout", &LUA_DEADLINE_S.to_string()])
        .args(&files)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .process_group(0)
        .spawn()
        .expect("luamotion test");
    let run = common::finish(child, Duration::from_secs(2 * LUA_DEADLINE_S + 30));
    let passed = |file: &Path| {
        run.stdout
            .lines()
            .any(|l| l.strip_prefix("PASS ").is_some_and(|r| r.trim_start().starts_with(&*file.to_string_lossy())))
    };
    blocks
        .iter()
        .zip(&files)
        .filter(|(_, file)| !passed(file))
        .map(|((at, program), _)| format!("{at}: the lua block did not pass\n{program}{}{}", run.stdout, run.stderr))
        .collect()
}

/// Every runnable block of the documents, with the document it is in.
fn runnable_blocks(language: &str) -> Vec<(PathBuf, Block)> {
    documents()
        .into_iter()
        .flat_map(|file| read(&file).blocks.into_iter().map(move |b| (file.clone(), b)))
        .filter(|(_, b)| b.runnable() && b.language() == language)
        .collect()
}

fn report(failures: Vec<String>) {
    assert!(failures.is_empty(), "{} problem(s) in the docs:\n\n{}", failures.len(), failures.join("\n\n"));
}

#[test]
fn every_link_and_anchor_resolves() {
    let root = repo_path("");
    let failures: Vec<String> = documents().iter().flat_map(|file| broken_links(&root, file, &read(file))).collect();
    report(failures);
}

#[test]
fn every_runnable_block_is_sh_or_lua() {
    let failures: Vec<String> =
        documents()
            .iter()
            .flat_map(|file| {
                read(file).blocks.into_iter().filter(|b| b.runnable() && !matches!(b.language(), "sh" | "lua")).map(
                    move |b| format!("{}:{}: runnable, but neither sh nor lua: {:?}", file.display(), b.line, b.info),
                )
            })
            .collect();
    report(failures);
}

#[test]
fn every_sh_runnable_block_runs() {
    let blocks = runnable_blocks("sh");
    assert!(blocks.iter().any(|(file, _)| file == Path::new("README.md")), "the README's commands are runnable blocks");
    let root = repo_path("");
    report(blocks.iter().filter_map(|(file, block)| run_sh(&root, file, block)).collect());
}

#[test]
fn every_lua_runnable_block_passes() {
    let blocks = runnable_blocks("lua");
    assert!(blocks.iter().any(|(file, _)| file == Path::new("README.md")), "the README's first program is runnable");
    let programs: Vec<(String, &str)> =
        blocks.iter().map(|(file, b)| (format!("{}:{}", file.display(), b.line), b.text.as_str())).collect();
    report(run_lua(&programs));
}

/// The checks can fail: a broken link, an anchor no heading has and a failing block are
/// found, each at its line; good links, a repeated heading's anchor and code are not.
#[test]
fn the_checks_find_what_is_broken() {
    let text = "\
# The page
## A `code` heading: with (punctuation)
## Again
## Again
See [here](#the-page), [there](#a-code-heading-with-punctuation), [twice](#again-1),
[gone](missing.md) and ![a picture](#no-such-heading). `[not a link](nowhere.md)`

```sh runnable
echo fine
```

```sh runnable
false
echo never
```

```text
[inside code](nowhere.md)
```
";
    let doc = Markdown::parse(text);
    assert_eq!(doc.anchors, ["the-page", "a-code-heading-with-punctuation", "again", "again-1"]);
    assert_eq!(doc.blocks.len(), 3);
    assert_eq!((doc.blocks[1].line, doc.blocks[1].language(), doc.blocks[1].runnable()), (12, "sh", true));
    assert!(!doc.blocks[2].runnable());

    let root = tempfile::tempdir().unwrap();
    std::fs::create_dir(root.path().join("scripts")).unwrap();
    std::fs::write(root.path().join("page.md"), text).unwrap();
    let broken = broken_links(root.path(), Path::new("page.md"), &doc);
    assert_eq!(broken.len(), 2, "{broken:?}");
    assert!(broken[0].starts_with("page.md:6: missing.md does not exist"), "{broken:?}");
    assert!(broken[1].starts_with("page.md:6: #no-such-heading names no heading"), "{broken:?}");

    assert_eq!(run_sh(root.path(), Path::new("page.md"), &doc.blocks[0]), None);
    let failed = run_sh(root.path(), Path::new("page.md"), &doc.blocks[1]).expect("false fails the block");
    assert!(failed.starts_with("page.md:12: the sh block failed"), "{failed}");
    assert!(!failed.contains("stdout:\nnever"), "bash -e stops at the failing line: {failed}");

    let lua = run_lua(&[("page.md:20".to_string(), "expect_eq(1, 2, \"one is two\")\n")]);
    assert_eq!(lua.len(), 1, "a failing expectation fails the block");
    assert!(lua[0].starts_with("page.md:20: the lua block did not pass"), "{}", lua[0]);
}
