//! docs/guide/options.md is the command line's own `--help`, command by command (written by
//! scripts/regen/guide-options.sh): a changed option fails here until the page is regenerated.

use std::process::Command;

#[test]
fn the_options_page_is_the_help_of_every_command() {
    let page = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/guide/options.md")).unwrap();
    let mut sections = 0;
    for section in page.split("\n## sppm-gpu ").skip(1) {
        let name = section.lines().next().unwrap().trim();
        let start = section.find("```text\n").unwrap_or_else(|| panic!("{name}: no help block")) + "```text\n".len();
        let end = start + section[start..].find("\n```").unwrap_or_else(|| panic!("{name}: unclosed block"));
        let documented = &section[start..end];
        let mut command = Command::new(env!("CARGO_BIN_EXE_sppm-gpu"));
        if name != "(render)" {
            command.arg(name);
        }
        let out = command.arg("--help").output().unwrap();
        assert!(out.status.success(), "{name}");
        let help = String::from_utf8(out.stdout).unwrap();
        assert_eq!(
            documented.trim_end(),
            help.trim_end(),
            "docs/guide/options.md, sppm-gpu {name}: regenerate it with `bash scripts/regen/guide-options.sh`"
        );
        sections += 1;
    }
    // The render and every subcommand but `help`.
    assert!(sections >= 10, "{sections} sections");
}
