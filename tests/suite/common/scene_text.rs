//! Scene files as text, for the tests that write or parse broken ones.

/// A valid scene of 12 lines; tests edit it or append to it.
pub const BASE: &str = r#"[render]
width = 8
height = 8
iterations = 1

[camera]
position = [0, 0, 5]
look_at = [0, 0, 0]
fov = 40

[materials]
white = { type = "diffuse", albedo = [0.5, 0.5, 0.5] }
"#;

/// A quad's keys, for `[[shapes]]` bodies (lines 14 to 18 after [`with_shape`]).
pub const QUAD: &str = r#"type = "quad"
corner = [0, 0, 0]
u = [1, 0, 0]
v = [0, 1, 0]
material = "white"
"#;

/// [`BASE`] with its first `old` replaced by `new`.
pub fn edit(old: &str, new: &str) -> String {
    assert!(BASE.contains(old), "BASE has no {old:?}");
    BASE.replacen(old, new, 1)
}

/// [`BASE`] and one `[[shapes]]` entry: the header is line 13, `body` starts at line 14.
pub fn with_shape(body: &str) -> String {
    format!("{BASE}[[shapes]]\n{body}")
}

/// [`BASE`] and one `[[lights]]` entry: the header is line 13, `body` starts at line 14.
pub fn with_light(body: &str) -> String {
    format!("{BASE}[[lights]]\n{body}")
}

/// A small valid Mitsuba scene of version `version`: a camera (8x8) and a rectangle emitting
/// `radiance`; `body` starts at line 10, after the 9 lines of the head.
pub fn mitsuba_with(version: &str, radiance: &str, body: &str) -> String {
    format!(
        r#"<scene version="{version}">
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
    </sensor>
    <shape type="rectangle">
        <emitter type="area"><rgb name="radiance" value="{radiance}"/></emitter>
    </shape>
{body}
</scene>
"#
    )
}
