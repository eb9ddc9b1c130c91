//! Hostile scenes (issue 40): input built to take the process down rather than to be
//! rendered. XML nested thousands deep, a shapegroup that instances itself, files that include
//! the next twice forty deep, instances that flatten to more primitives than memory holds,
//! links to /dev/zero. Each must be an error naming the file and line (and key), quickly,
//! never a stack overflow, an abort or a process killed for memory. Also the two transform
//! messages of the issue: a projective `<matrix>` and a scale that overflows.

use crate::common;

use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestCaseError};
use sppm_gpu::scene::{self, Scene, SceneError};
use std::path::Path;
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Writes `files` (name, text) into `dir`.
fn write(dir: &Path, files: &[(String, String)]) {
    for (name, text) in files {
        std::fs::write(dir.join(name), text).unwrap();
    }
}

/// The lines before the body of [`scene_with`].
const HEAD_LINES: usize = 9;

/// A small valid scene of version `version` with `body` from line 10 on: a camera and a lit
/// rectangle (2 triangles).
fn scene_with(version: &str, body: &str) -> String {
    crate::common::scene_text::mitsuba_with(version, "1", body)
}

/// Loads `dir/main.xml`; it must fail, and the error must name a file in `dir` and a line.
#[track_caller]
fn refused(dir: &Path) -> SceneError {
    let e = match scene::load(&dir.join("main.xml")) {
        Ok(_) => panic!("{} loaded", dir.display()),
        Err(e) => e,
    };
    assert!(e.file.starts_with(dir) && e.file.is_file(), "{e}");
    assert!(e.line.is_some(), "{e}");
    e
}

/// `sppm-gpu info scene`: its exit status and stderr.
fn info(scene: &Path) -> (Option<i32>, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_sppm-gpu"))
        .arg("info")
        .arg(scene)
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .output()
        .expect("the binary runs");
    (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned())
}

/// 10,000 nested elements, one a line: refused at the first element past 256 deep, in the
/// library (whose test thread has a small stack) and in the binary, which exits with 1 rather
/// than aborting on a stack overflow (134).
#[test]
fn xml_nested_ten_thousand_deep_is_refused() {
    let dir = common::scratch("hostile-deep");
    let n = 10_000;
    let body = "<shape type=\"rectangle\">\n".repeat(n) + &"</shape>\n".repeat(n);
    write(&dir, &[("main.xml".into(), scene_with("3.0.0", &body))]);
    let e = refused(&dir);
    // <scene> is depth 1 and the first nested shape depth 2, on line HEAD_LINES + 1.
    assert_eq!(e.line, Some(HEAD_LINES + 256), "{e}");
    assert!(e.message.contains("nests more than 256 elements deep"), "{e}");

    let (code, stderr) = info(&dir.join("main.xml"));
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains(&format!("main.xml:{}", HEAD_LINES + 256)), "{stderr}");

    // Depth counts through includes: 200 here and 100 in the included file.
    let outer = "<shape type=\"rectangle\">\n".repeat(199) + "<include filename=\"inner.xml\"/>\n" + &"</shape>\n".repeat(199);
    let inner = format!(
        "<scene version=\"3.0.0\">\n{}{}</scene>\n",
        "<shape type=\"rectangle\">\n".repeat(100),
        "</shape>\n".repeat(100)
    );
    write(&dir, &[("main.xml".into(), scene_with("3.0.0", &outer)), ("inner.xml".into(), inner)]);
    let e = refused(&dir);
    assert_eq!(e.file.file_name().unwrap(), "inner.xml", "{e}");
    // The include is depth 201, and so is the first shape it brings (line 2): depth 257 is
    // line 2 + 56.
    assert_eq!(e.line, Some(2 + 56), "{e}");
}

/// The issue's shapegroup that instances itself: Mitsuba (0.6 and 3) refuses an instance
/// inside a shapegroup, "Nested instancing is not permitted"; so do we, at the inner
/// instance, naming the group. It used to recurse until the stack overflowed.
#[test]
fn shapegroup_instancing_itself_is_refused() {
    let dir = common::scratch("hostile-self-instance");
    let body = r#"<shape type="shapegroup" id="g">
    <shape type="instance"><ref id="g"/></shape>
</shape>
<shape type="instance"><ref id="g"/></shape>"#;
    for version in ["3.0.0", "0.5.0"] {
        write(&dir, &[("main.xml".into(), scene_with(version, body))]);
        let e = refused(&dir);
        assert_eq!(e.line, Some(HEAD_LINES + 2), "{e}");
        assert_eq!(e.key.as_deref(), Some("type"), "{e}");
        assert!(e.message.contains("shapegroup \"g\"") && e.message.contains("nested instancing is not permitted"), "{e}");
    }
    // A cycle of references that no group rule catches.
    let body = r#"<bsdf type="twosided" id="a"><ref id="b"/></bsdf>
<bsdf type="twosided" id="b"><ref id="a"/></bsdf>
<shape type="sphere"><ref id="a"/></shape>"#;
    write(&dir, &[("main.xml".into(), scene_with("3.0.0", body))]);
    let e = refused(&dir);
    assert_eq!((e.line, e.key.as_deref()), (Some(HEAD_LINES + 2), Some("id")), "{e}");
    assert!(e.message.contains("reference cycle"), "{e}");
}

/// Thirty-nine shapegroups each instancing the one before twice flatten to 2^39 spheres;
/// that used to abort when the allocation failed. Nested instancing is refused first, at the
/// first instance inside a group.
#[test]
fn nested_shapegroups_of_two_to_the_39_spheres_are_refused() {
    let dir = common::scratch("hostile-nested-groups");
    let mut body = String::from("<shape type=\"shapegroup\" id=\"g0\"><shape type=\"sphere\"/></shape>\n");
    for i in 1..=39 {
        let copy = format!("<shape type=\"instance\"><ref id=\"g{}\"/></shape>", i - 1);
        body += &format!("<shape type=\"shapegroup\" id=\"g{i}\">\n{copy}\n{copy}\n</shape>\n");
    }
    body += "<shape type=\"instance\"><ref id=\"g39\"/></shape>";
    write(&dir, &[("main.xml".into(), scene_with("3.0.0", &body))]);
    let start = Instant::now();
    let e = refused(&dir);
    assert!(start.elapsed() < Duration::from_secs(10));
    // g0 is line 10, g1 opens on line 11 and its first instance is line 12.
    assert_eq!(e.line, Some(HEAD_LINES + 3), "{e}");
    assert!(e.message.contains("inside shapegroup \"g1\""), "{e}");
}

/// An emitter inside a shapegroup: Mitsuba refuses it ("Instancing of emitters is not
/// supported"), where we used to copy the light into each instance.
#[test]
fn emitters_inside_shapegroups_are_refused() {
    let dir = common::scratch("hostile-group-emitter");
    let body = r#"<shape type="shapegroup" id="g">
    <shape type="sphere">
        <emitter type="area"><rgb name="radiance" value="1"/></emitter>
    </shape>
</shape>
<shape type="instance"><ref id="g"/></shape>"#;
    write(&dir, &[("main.xml".into(), scene_with("3.0.0", body))]);
    let e = refused(&dir);
    assert_eq!(e.line, Some(HEAD_LINES + 3), "{e}");
    assert!(e.message.contains("instancing of emitters is not supported"), "{e}");
}

/// Forty files, each including the next twice (no cycle), would read 2^40 files; the include
/// budget stops them after 16,384 reads, in a second or so.
#[test]
fn doubling_includes_forty_deep_are_refused_quickly() {
    let dir = common::scratch("hostile-include-bomb");
    let mut files = vec![("main.xml".to_string(), scene_with("3.0.0", "<include filename=\"f1.xml\"/>"))];
    for i in 1..40 {
        let next = format!("<include filename=\"f{}.xml\"/>\n", i + 1);
        files.push((format!("f{i}.xml"), format!("<scene version=\"3.0.0\">\n{next}{next}</scene>\n")));
    }
    files.push(("f40.xml".into(), "<scene version=\"3.0.0\">\n<shape type=\"sphere\"/>\n</scene>\n".into()));
    write(&dir, &files);
    let start = Instant::now();
    let e = refused(&dir);
    assert!(start.elapsed() < Duration::from_secs(20), "{:?}", start.elapsed());
    assert_eq!(e.key.as_deref(), Some("filename"), "{e}");
    assert!(e.message.contains("more than 16384 includes"), "{e}");
}

/// A group of 1024 disks (256 triangles each) instanced 16,384 times is 2^32 triangles: once
/// the first copy is made, the other copies are counted against the budget before any is
/// made, and refused at that instance.
#[test]
fn instances_beyond_memory_are_refused_before_they_are_copied() {
    let dir = common::scratch("hostile-instance-bomb");
    let disks = "<shape type=\"disk\"/>\n".repeat(1024);
    let instances = "<shape type=\"instance\"><ref id=\"g\"/></shape>\n".repeat(16_384);
    let body = format!("<shape type=\"shapegroup\" id=\"g\">\n{disks}</shape>\n{instances}");
    write(&dir, &[("main.xml".into(), scene_with("3.0.0", &body))]);
    let start = Instant::now();
    let e = refused(&dir);
    assert!(start.elapsed() < Duration::from_secs(20), "{:?}", start.elapsed());
    // The group is lines 10 to 1035; the first instance line 1036.
    assert_eq!((e.line, e.key.as_deref()), (Some(HEAD_LINES + 1027), Some("id")), "{e}");
    assert!(
        e.message.starts_with("the scene expands to 4294967298 triangles and spheres (16384 instances of shapegroup \"g\" of line 10, 262144 primitives each): more than the "),
        "{e}"
    );
}

/// One file of 100,000 elements reads in linear time: each element's line is found by a
/// binary search, where roxmltree's `text_pos_at` scanned the file from its start for each
/// (minutes for this file).
#[test]
fn a_large_flat_file_reads_in_linear_time() {
    let dir = common::scratch("hostile-flat");
    let spheres = "<shape type=\"sphere\"><float name=\"radius\" value=\"0.01\"/></shape>\n".repeat(100_000);
    write(&dir, &[("main.xml".into(), scene_with("3.0.0", &spheres))]);
    let start = Instant::now();
    let s = scene::load(&dir.join("main.xml")).unwrap();
    assert!(start.elapsed() < Duration::from_secs(20), "{:?}", start.elapsed());
    assert_eq!(s.spheres.len(), 100_000);
    assert_eq!(s.shapes.last().unwrap().line, HEAD_LINES + 100_000);
}

/// A mesh, an include or a texture that is a link to /dev/zero: refused as not a regular file
/// at the parameter that names it, where reading it would never end.
#[cfg(unix)]
#[test]
fn links_to_dev_zero_are_refused() {
    let dir = common::scratch("hostile-dev-zero");
    for name in ["zero.xml", "zero.obj", "zero.png"] {
        std::os::unix::fs::symlink("/dev/zero", dir.join(name)).unwrap();
    }
    let cases = [
        ("<include filename=\"zero.xml\"/>", "filename"),
        ("<shape type=\"obj\"><string name=\"filename\" value=\"zero.obj\"/></shape>", "filename"),
        (
            "<shape type=\"sphere\"><bsdf type=\"diffuse\"><texture type=\"bitmap\" name=\"reflectance\">\n\
             <string name=\"filename\" value=\"zero.png\"/></texture></bsdf></shape>",
            "filename",
        ),
    ];
    for (body, key) in cases {
        write(&dir, &[("main.xml".into(), scene_with("3.0.0", body))]);
        let e = refused(&dir);
        assert_eq!(e.key.as_deref(), Some(key), "{e}");
        assert!(e.message.contains("not a regular file"), "{e}");
    }
    // A TOML scene's mesh.
    let toml = format!(
        "{}[[shapes]]\ntype = \"mesh\"\nmaterial = \"white\"\nfile = \"zero.obj\"\nemission = [1, 1, 1]\n",
        crate::common::scene_text::BASE
    );
    std::fs::write(dir.join("scene.toml"), toml).unwrap();
    let e = scene::load(&dir.join("scene.toml")).unwrap_err();
    assert_eq!((e.line, e.key.as_deref()), (Some(16), Some("shapes[0].file")), "{e}");
    assert!(e.message.contains("not a regular file"), "{e}");
}

/// A `<matrix>` with the bottom row 1 1 1 2: Mitsuba 3 applies it as affine, and so do we, with
/// a warning at the matrix; Mitsuba 0.6 divides by w, which is refused in a 0.x scene.
#[test]
fn projective_matrices_warn_in_mitsuba_3_and_are_refused_in_0_x() {
    let dir = common::scratch("hostile-projective");
    let body = r#"<shape type="rectangle">
    <transform name="to_world">
        <matrix value="2 0 0 1  0 2 0 0  0 0 2 0  1 1 1 2"/>
    </transform>
</shape>"#;
    write(&dir, &[("main.xml".into(), scene_with("3.0.0", body))]);
    let (s, warnings) = scene::mitsuba::load_with_warnings(&dir.join("main.xml"), &[]);
    let s: Scene = s.unwrap();
    let warning = warnings.iter().find(|w| w.message.contains("bottom row")).expect("a warning");
    assert_eq!((warning.line, warning.key.as_deref()), (Some(HEAD_LINES + 3), Some("value")), "{warning}");
    assert!(warning.message.starts_with("the bottom row 1 1 1 2 is ignored: "), "{warning}");
    // The top three rows: (x, y) -> (2x + 1, 2y).
    let corners: Vec<_> = s.triangles[2..].iter().flat_map(|t| t.p).collect();
    assert!(corners.contains(&glam::Vec3::new(3.0, 2.0, 0.0)) && corners.contains(&glam::Vec3::new(-1.0, -2.0, 0.0)));

    write(&dir, &[("main.xml".into(), scene_with("0.5.0", body))]);
    let e = refused(&dir);
    assert_eq!((e.line, e.key.as_deref()), (Some(HEAD_LINES + 3), Some("value")), "{e}");
    assert!(e.message.contains("divide each transformed point by its w"), "{e}");
}

/// A scale of 1e30 overflows 32-bit floats, whatever the shape; it used to be reported as
/// scaling a disk to nothing (its cross products are inf - inf) and a sphere as uneven.
/// A scale of 1e-30 does scale a disk to nothing.
#[test]
fn huge_scales_overflow_rather_than_vanish() {
    let dir = common::scratch("hostile-scale");
    let shape = |kind: &str, scale: &str| {
        format!("<shape type=\"{kind}\">\n<transform name=\"to_world\"><scale value=\"{scale}\"/></transform>\n</shape>")
    };
    for kind in ["disk", "rectangle", "cube", "sphere"] {
        write(&dir, &[("main.xml".into(), scene_with("3.0.0", &shape(kind, "1e30")))]);
        let e = refused(&dir);
        assert_eq!((e.line, e.key.as_deref()), (Some(HEAD_LINES + 1), Some("to_world")), "{kind}: {e}");
        assert!(e.message.contains("beyond the range of 32-bit floats"), "{kind}: {e}");
    }
    write(&dir, &[("main.xml".into(), scene_with("3.0.0", &shape("disk", "1e-30")))]);
    assert!(refused(&dir).message.contains("scales it to nothing"));
}

/// One random scene of the property below: a shapegroup whose shapes come through
/// `group_depth` levels of files each including the next `group_fan` times, instanced through
/// `instance_depth` levels of `instance_fan`, and perhaps one hostile thing.
#[derive(Clone, Debug)]
struct Nest {
    leaves: Vec<usize>,
    group_depth: u32,
    group_fan: usize,
    instance_depth: u32,
    instance_fan: usize,
    hostile: usize,
}

/// Leaf shapes: element, triangles, spheres.
const LEAVES: [(&str, usize, usize); 3] = [
    ("<shape type=\"sphere\"><float name=\"radius\" value=\"0.1\"/></shape>", 0, 1),
    ("<shape type=\"rectangle\"/>", 2, 0),
    ("<shape type=\"cube\"/>", 12, 0),
];

/// The hostile things, the file each is put in and what the error says: none; an instance
/// in the group; the last instance file including the first; 300 nested elements; two BSDFs
/// referring to each other; an emitter in the group.
const HOSTILE: [(&str, &str); 6] = [
    ("", ""),
    ("g", "nested instancing is not permitted"),
    ("i", "includes itself"),
    ("g", "nests more than 256 elements deep"),
    ("main", "reference cycle"),
    ("g", "instancing of emitters is not supported"),
];

/// Writes `nest`'s files into `dir`; the triangles and spheres it expands to.
fn write_nest(dir: &Path, nest: &Nest) -> (usize, usize) {
    let chain = |prefix: &str, depth: u32, fan: usize, leaf: String| -> Vec<(String, String)> {
        (0..=depth)
            .map(|level| {
                let body = if level == depth {
                    leaf.clone()
                } else {
                    format!("<include filename=\"{prefix}{}.xml\"/>\n", level + 1).repeat(fan)
                };
                (format!("{prefix}{level}.xml"), format!("<scene version=\"3.0.0\">\n{body}</scene>\n"))
            })
            .collect()
    };
    let hostile = |file: &str, text: &str| if HOSTILE[nest.hostile].0 == file { text.to_owned() } else { String::new() };
    let mut leaf: String = nest.leaves.iter().map(|&l| format!("{}\n", LEAVES[l].0)).collect();
    leaf += &hostile(
        "g",
        &match nest.hostile {
            1 => "<shape type=\"instance\"><ref id=\"g\"/></shape>\n".to_owned(),
            3 => "<shape type=\"sphere\">\n".repeat(300) + &"</shape>\n".repeat(300),
            _ => "<shape type=\"sphere\"><emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/></emitter></shape>\n".into(),
        },
    );
    let instance =
        "<shape type=\"instance\"><ref id=\"g\"/><transform name=\"to_world\"><translate x=\"0.5\"/></transform></shape>\n";
    let mut files = chain("g", nest.group_depth, nest.group_fan, leaf);
    files.extend(chain(
        "i",
        nest.instance_depth,
        nest.instance_fan,
        format!("{instance}{}", hostile("i", "<include filename=\"i0.xml\"/>\n")),
    ));
    let cycle =
        "<bsdf type=\"twosided\" id=\"a\"><ref id=\"b\"/></bsdf>\n<bsdf type=\"twosided\" id=\"b\"><ref id=\"a\"/></bsdf>\n";
    let main = format!(
        "{}<shape type=\"shapegroup\" id=\"g\"><include filename=\"g0.xml\"/></shape>\n<include filename=\"i0.xml\"/>",
        hostile("main", cycle)
    );
    files.push(("main.xml".into(), scene_with("3.0.0", &main)));
    write(dir, &files);
    let copies = nest.group_fan.pow(nest.group_depth) * nest.instance_fan.pow(nest.instance_depth);
    let per_leaf = |pick: fn(&(&str, usize, usize)) -> usize| nest.leaves.iter().map(|&l| pick(&LEAVES[l])).sum::<usize>();
    (2 + copies * per_leaf(|l| l.1), copies * per_leaf(|l| l.2))
}

fn nest() -> impl Strategy<Value = Nest> {
    (
        prop::collection::vec(0..LEAVES.len(), 1..=3),
        0..=3u32,
        1..=3usize,
        0..=3u32,
        1..=3usize,
        // Half the cases are not hostile.
        prop_oneof![Just(0), 0..HOSTILE.len()],
    )
        .prop_map(|(leaves, group_depth, group_fan, instance_depth, instance_fan, hostile)| Nest {
            leaves,
            group_depth,
            group_fan,
            instance_depth,
            instance_fan,
            hostile,
        })
}

fn config() -> Config {
    let mut config = Config::default(); // reads PROPTEST_* from the environment
    if std::env::var_os("PROPTEST_CASES").is_none() {
        config.cases = 96;
    }
    if std::env::var_os("PROPTEST_RNG_SEED").is_none() {
        config.rng_seed = RngSeed::Fixed(0x40);
    }
    config.failure_persistence = None;
    config
}

/// Cases so far, for their folders.
static CASE: AtomicUsize = AtomicUsize::new(0);

proptest! {
    #![proptest_config(config())]

    /// Includes and instances nested and multiplied at random: each scene loads with the
    /// primitives the test counts, or (when it has a hostile thing) is refused with the error
    /// that thing calls for, in the file it is in, at a line. At most 27 files each way and 27
    /// copies of 36 primitives, so each case is small by construction; 96 cases.
    #[test]
    fn nested_includes_and_instances_load_exactly_or_are_refused(nest in nest()) {
        let dir = common::scratch(&format!("hostile-nest-{}", CASE.fetch_add(1, Ordering::Relaxed)));
        let checked = check_nest(&dir, &nest);
        if checked.is_err() {
            // A failing case's files stay, as a panicking test's do.
            dir.keep();
        }
        checked?;
    }
}

/// [`nested_includes_and_instances_load_exactly_or_are_refused`]'s case `nest`, written into
/// `dir` and loaded.
fn check_nest(dir: &Path, nest: &Nest) -> Result<(), TestCaseError> {
    let (triangles, spheres) = write_nest(dir, nest);
    let (file, phrase) = HOSTILE[nest.hostile];
    match scene::load(&dir.join("main.xml")) {
        Ok(s) => {
            prop_assert_eq!(nest.hostile, 0);
            prop_assert_eq!((s.triangles.len(), s.spheres.len()), (triangles, spheres));
        }
        Err(e) => {
            prop_assert!(nest.hostile != 0, "{}", e);
            prop_assert!(e.message.contains(phrase), "{}", e);
            prop_assert!(e.line.is_some(), "{}", e);
            let name = e.file.file_name().unwrap().to_string_lossy().into_owned();
            prop_assert!(name.starts_with(file) && e.file.starts_with(dir), "{}", e);
        }
    }
    Ok(())
}
