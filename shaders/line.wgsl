// Coloured vertices with alpha: line lists (ghost trajectories, the launcher, outlines) and,
// with a triangle-list pipeline, translucent surfaces (walls).

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec4<f32>,
};

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) colour: vec4<f32>) -> VsOut {
    var out: VsOut;
    out.clip = globals.proj * globals.view * vec4(position, 1.0);
    out.colour = decode(colour);
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    return in.colour;
}
