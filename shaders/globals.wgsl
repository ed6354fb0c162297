// Shared by every pipeline (prepended to each shader file by the renderer): the camera and the
// frame's constants, and the sRGB decoding of the colours the CPU sends as bytes.

struct Globals {
    view: mat4x4<f32>,
    proj: mat4x4<f32>,
    // x, y, width, height of the 3D viewport (px).
    viewport: vec4<f32>,
    // Direction towards the light, view space (w unused).
    light: vec4<f32>,
    // x: ground height (relative to the render origin), y: 1 if the scene has a ground,
    // z: grid half extent (m), w: smallest drawn sphere radius (px).
    ground: vec4<f32>,
    // xy: render origin modulo the major grid spacing (m), z: minor spacing, w: major spacing.
    grid: vec4<f32>,
    // xy: the render origin's own x, y (m), zw: camera target x, y relative to the origin.
    axes: vec4<f32>,
};

@group(0) @binding(0) var<uniform> globals: Globals;

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    let low = c / 12.92;
    let high = pow((c + vec3(0.055)) / 1.055, vec3(2.4));
    return select(high, low, c <= vec3(0.04045));
}

fn decode(c: vec4<f32>) -> vec4<f32> {
    return vec4(srgb_to_linear(c.rgb), c.a);
}

// A vertex the rasteriser drops: outside the clip volume on every side.
const CULLED: vec4<f32> = vec4<f32>(2.0, 2.0, 2.0, 1.0);
