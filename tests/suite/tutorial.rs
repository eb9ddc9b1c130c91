//! The guide's tutorial and reference work as written. docs/guide/first-scene.md: each TOML
//! excerpt is in the scene file its step renders, and every `sppm-gpu ...` command in its
//! code blocks runs (on a 32x32 image for half a second) and writes the image the page says.
//! docs/guide/scene-format.md: every TOML example loads. And the guide speaks to users: no page
//! of docs/guide/ cites a session or an issue of the project's history (that is the journal's).

use crate::common;
use sppm_gpu::scene;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(relative: &str) -> String {
    std::fs::read_to_string(root().join(relative)).unwrap_or_else(|e| panic!("{relative}: {e}"))
}

/// The fenced code blocks of a Markdown page, in order: the info string (`toml`, `sh`) and
/// the lines between the fences.
fn code_blocks(text: &str) -> Vec<(String, Vec<String>)> {
    let mut blocks = Vec::new();
    let mut open: Option<(String, Vec<String>)> = None;
    for line in text.lines() {
        let fence = line.trim_start().starts_with("```");
        match &mut open {
            Some(_) if fence => blocks.push(open.take().unwrap()),
            Some((_, lines)) => lines.push(line.to_owned()),
            None if fence => open = Some((line.trim_start().trim_start_matches('`').trim().to_owned(), Vec::new())),
            None => {}
        }
    }
    assert!(open.is_none(), "a code block is not closed");
    blocks
}

/// The arguments of each `sppm-gpu ...` command of a shell block: continuation lines joined,
/// trailing `# comments` dropped.
fn commands(lines: &[String]) -> Vec<Vec<String>> {
    let mut joined = Vec::new();
    let mut current = String::new();
    for line in lines {
        let line = line.split(" #").next().unwrap().trim_end();
        match line.strip_suffix('\\') {
            Some(head) => current.push_str(head),
            None => {
                current.push_str(line);
                joined.push(std::mem::take(&mut current));
            }
        }
    }
    joined
        .iter()
        .filter_map(|line| line.trim().strip_prefix("sppm-gpu "))
        .map(|args| {
            assert!(!args.contains(['"', '\'', '$', '|', '>']), "quote, variable or redirection in `{args}`: not run");
            args.split_whitespace().map(str::to_owned).collect()
        })
        .collect()
}

/// The lines of a TOML excerpt that carry a value or a header: not blank, not comments.
fn significant(lines: &[String]) -> Vec<&str> {
    lines.iter().map(|l| l.trim()).filter(|l| !l.is_empty() && !l.starts_with('#')).collect()
}

/// Whether every line of `excerpt` is a line of `file`, in the same order.
fn in_order(excerpt: &[&str], file: &str) -> Result<(), String> {
    let mut lines = file.lines().map(str::trim);
    for wanted in excerpt {
        if !lines.any(|l| l == *wanted) {
            return Err(format!("`{wanted}` (or the lines before it, in order)"));
        }
    }
    Ok(())
}

/// A TOML excerpt of the tutorial (its lines) and the scene file it belongs to.
type Excerpt = (Vec<String>, String);

/// The tutorial's steps: each TOML excerpt with the scene file of the next command that
/// renders one, and every command.
fn tutorial() -> (Vec<Excerpt>, Vec<Vec<String>>) {
    let mut excerpts = Vec::new();
    let mut pending = Vec::new();
    let mut all = Vec::new();
    for (info, lines) in code_blocks(&read("docs/guide/first-scene.md")) {
        match info.as_str() {
            "toml" => pending.push(lines),
            "sh" => {
                for args in commands(&lines) {
                    if args[0].ends_with(".toml") {
                        excerpts.extend(pending.drain(..).map(|lines| (lines, args[0].clone())));
                    }
                    all.push(args);
                }
            }
            other => panic!("docs/guide/first-scene.md: a code block of `{other}`: expected toml or sh"),
        }
    }
    assert!(pending.is_empty(), "docs/guide/first-scene.md ends with TOML that no command renders");
    (excerpts, all)
}

#[test]
fn tutorial_excerpts_are_in_the_files_it_renders() {
    let (excerpts, commands) = tutorial();
    assert!(excerpts.len() >= 5 && commands.len() >= 5, "{} excerpts, {} commands", excerpts.len(), commands.len());
    for (lines, scene) in &excerpts {
        let file = read(scene);
        if let Err(missing) = in_order(&significant(lines), &file) {
            panic!("docs/guide/first-scene.md shows a line that {scene} lacks: {missing}");
        }
    }
    // The last step's file is the whole scene, and every step's file loads.
    assert_eq!(excerpts.last().unwrap().1, "scenes/tutorial/first-scene.toml");
    for (_, scene) in &excerpts {
        scene::load(&root().join(scene)).unwrap_or_else(|e| panic!("{e}"));
    }
}

/// A command of the page as the test runs it, in `dir`: scene paths made absolute, and a
/// render cut to 32x32 pixels and half a second of passes (`--time-limit` alone).
fn as_run(args: &[String]) -> Vec<String> {
    let render = args[0].ends_with(".toml");
    let mut out = Vec::new();
    let mut i = 0;
    while i < args.len() {
        let arg = &args[i];
        if render && ["--time-limit", "--iterations", "--width", "--height"].contains(&arg.as_str()) {
            i += 2;
            continue;
        }
        out.push(if arg.starts_with("scenes/") { root().join(arg).display().to_string() } else { arg.clone() });
        i += 1;
    }
    if render {
        out.extend(["--width", "32", "--height", "32", "--time-limit", "0.5"].map(str::to_owned));
    }
    out
}

#[test]
fn tutorial_commands_run_and_write_their_images() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("tutorial");
    for args in tutorial().1 {
        let run = as_run(&args);
        let output = Command::new(env!("CARGO_BIN_EXE_sppm-gpu"))
            .args(&run)
            .current_dir(&dir)
            .env("XDG_RUNTIME_DIR", std::env::temp_dir())
            .output()
            .expect("the binary runs");
        let stderr = String::from_utf8_lossy(&output.stderr);
        let command = format!("sppm-gpu {}", args.join(" "));
        assert_eq!(output.status.code(), Some(0), "{command}:\n{stderr}");
        if !args[0].ends_with(".toml") {
            continue;
        }
        // The page says: the method is named on stderr, and without -o the image is
        // SCENE.exr in the current directory.
        assert!(stderr.contains(&format!("rendering {} with ", run[0])), "{command}:\n{stderr}");
        let image = match args.iter().position(|a| a == "-o") {
            Some(i) => dir.join(&args[i + 1]),
            None => dir.join(Path::new(&args[0]).with_extension("exr").file_name().unwrap()),
        };
        let size = std::fs::metadata(&image).map(|m| m.len()).unwrap_or(0);
        assert!(size > 0, "{command}: no image at {}:\n{stderr}", image.display());
    }
}

/// Every ```toml example of the scene format's reference loads: alone when it is a whole
/// scene, else after a base of `[render]`, `[camera]` and the material `white`, each added
/// only when the example has no table of that name. File names resolve against `scenes/`.
#[test]
fn scene_format_examples_load() {
    let page = read("docs/guide/scene-format.md");
    let mut checked = 0;
    for (info, lines) in code_blocks(&page) {
        if info != "toml" {
            continue;
        }
        let example = lines.join("\n");
        let has = |header: &str| lines.iter().any(|l| l.trim() == header);
        let mut text = String::new();
        if !has("[render]") {
            text.push_str("[render]\nwidth = 8\nheight = 8\niterations = 1\n");
        }
        if !has("[camera]") {
            text.push_str("[camera]\nposition = [0, 1, 5]\nlook_at = [0, 1, 0]\nfov = 40\n");
        }
        if !has("[materials]") {
            text.push_str("[materials]\nwhite = { type = \"diffuse\", albedo = [0.8, 0.8, 0.8] }\n");
        }
        text.push_str(&example);
        if let Err(e) = scene::load_str(&text, &root().join("scenes/example.toml")) {
            panic!("docs/guide/scene-format.md: an example does not load: {e}\n{example}");
        }
        checked += 1;
    }
    assert!(checked >= 20, "only {checked} TOML examples in docs/guide/scene-format.md");
}

/// The part of `page` under the heading `heading` (a whole line, `## ...`), up to the next
/// heading of its level or above; with `intro`, only up to its first subheading.
fn section<'a>(page: &'a str, heading: &str, intro: bool) -> &'a str {
    let level = heading.chars().take_while(|&c| c == '#').count();
    let start = page.find(&format!("\n{heading}\n")).unwrap_or_else(|| panic!("no heading `{heading}` in the page")) + 1;
    let body = &page[start + heading.len()..];
    let mut offset = 0;
    let mut fence = false;
    for line in body.split_inclusive('\n') {
        fence ^= line.trim_start().starts_with("```");
        let hashes = line.chars().take_while(|&c| c == '#').count();
        if !fence && hashes > 0 && line[hashes..].starts_with(' ') && (hashes <= level || intro) {
            break;
        }
        offset += line.len();
    }
    &body[..offset]
}

/// The keys an entry allows, from the loader's own error for an unknown key in `text`
/// ("unknown key `zzz`; allowed keys: a, b, c").
fn allowed_keys(text: &str) -> Vec<String> {
    let error = scene::load_str(text, &root().join("scenes/example.toml")).expect_err("an unknown key is an error");
    let (_, keys) = error.message.split_once("allowed keys: ").unwrap_or_else(|| panic!("{error}"));
    keys.split(", ").map(str::to_owned).collect()
}

/// The types the loader names for an unknown `type` in `text` ("expected one of: a, b").
fn types(text: &str) -> Vec<String> {
    let error = scene::load_str(text, Path::new("example.toml")).expect_err("an unknown type is an error");
    let (_, names) = error.message.split_once("expected one of: ").unwrap_or_else(|| panic!("{error}"));
    names.split(", ").map(str::to_owned).collect()
}

/// The scene format's reference names every key the loader allows, each in the section of
/// its table or type (or the intro of its table, for the keys every type takes), and has a
/// section for every material, shape and light type: asked of the loader itself, through the
/// keys its "unknown key" errors list.
#[test]
fn scene_format_names_every_key() {
    let page = read("docs/guide/scene-format.md");
    let base = "[render]\nwidth = 8\nheight = 8\niterations = 1\n[camera]\nposition = [0, 1, 5]\nlook_at = [0, 1, 0]\nfov = 40\n";
    let white = "[materials]\nwhite = { type = \"diffuse\", albedo = [0.5, 0.5, 0.5] }\n";
    let mut missing = Vec::new();
    let mut check = |keys: Vec<String>, places: &[&str], what: &str| {
        for key in keys {
            if !places.iter().any(|p| p.contains(&format!("`{key}`"))) {
                missing.push(format!("`{key}` of {what}"));
            }
        }
    };
    let render = section(&page, "## `[render]`", false);
    check(allowed_keys(&base.replace("iterations = 1\n", "iterations = 1\nzzz = 1\n")), &[render], "[render]");
    let camera = section(&page, "## `[camera]`", false);
    check(allowed_keys(&base.replace("fov = 40\n", "fov = 40\nzzz = 1\n")), &[camera], "[camera]");
    let media = section(&page, "## `[media]`", false);
    check(allowed_keys(&format!("{base}[media.fog]\nzzz = 1\n")), &[media], "[media]");
    let textures = section(&page, "### Textures", false);
    let texture = "[materials]\nm = { type = \"diffuse\", texture = { file = \"x.png\", zzz = 1 } }\n";
    check(allowed_keys(&format!("{base}{texture}")), &[textures], "a texture table");
    let tables = [
        ("## `[materials]`", "[materials]\nm = { type = \"TYPE\", zzz = 1 }\n"),
        ("## `[[shapes]]`", "[[shapes]]\ntype = \"TYPE\"\nzzz = 1\n"),
        ("## `[[lights]]`", "[[lights]]\ntype = \"TYPE\"\nzzz = 1\n"),
    ];
    for (heading, entry) in tables {
        let intro = section(&page, heading, true);
        let materials = if heading.contains("materials") { "" } else { white };
        for name in types(&format!("{base}{materials}{}", entry.replace("TYPE", "zzz"))) {
            let own = section(&page, &format!("### {name}"), false);
            check(allowed_keys(&format!("{base}{materials}{}", entry.replace("TYPE", &name))), &[own, intro], &name);
        }
    }
    assert!(missing.is_empty(), "docs/guide/scene-format.md lacks keys the loader reads:\n{}", missing.join("\n"));
}

/// `session N`, `sessions N`, `issue N` or `issues N` (any case), or "the study": history,
/// which belongs in the journal.
fn history(line: &str) -> Option<&'static str> {
    let lower = line.to_lowercase();
    for word in ["session ", "sessions ", "issue ", "issues "] {
        let mut rest = lower.as_str();
        while let Some(at) = rest.find(word) {
            rest = &rest[at + word.len()..];
            if rest.starts_with(|c: char| c.is_ascii_digit()) {
                return Some(word);
            }
        }
    }
    lower.contains("the study").then_some("the study")
}

#[test]
fn guide_pages_cite_no_sessions_or_issues() {
    assert_eq!(history("see Session 12, the figures"), Some("session "));
    assert_eq!(history("(issues 3 to 5)"), Some("issues "));
    assert_eq!(history("the session's log, issue tracker, [j](../journal/session-12.md#issue-26)"), None);
    let mut found = Vec::new();
    for entry in std::fs::read_dir(root().join("docs/guide")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "md") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        for (n, line) in text.lines().enumerate() {
            if let Some(word) = history(line) {
                found.push(format!("{}:{}: `{}`: {line}", path.display(), n + 1, word.trim()));
            }
        }
    }
    assert!(found.is_empty(), "the guide cites the project's history (move it to docs/journal/):\n{}", found.join("\n"));
}
