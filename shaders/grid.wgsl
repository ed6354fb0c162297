// The ground: a large square on the plane z = ground height (z = 0 without a ground), centred
// under the camera target, with anti-aliased grid lines (minor and major spacing chosen by the
// camera distance), the world x axis in red and the y axis in green, fading with distance.

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) local: vec2<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) vi: u32) -> VsOut {
    let corner = vec2(f32(vi & 1u), f32((vi >> 1u) & 1u)) * 2.0 - 1.0;
    let extent = globals.ground.z;
    let xy = globals.axes.zw + corner * extent;
    var out: VsOut;
    out.clip = globals.proj * globals.view * vec4(xy, globals.ground.x, 1.0);
    out.local = xy;
    return out;
}

// Coverage of lines every `spacing` metres at coordinate `x` (0 off the line, 1 on it), faded
// out where the lines come closer than about 4 pixels so distant ground does not turn to moire.
fn lines(x: vec2<f32>, spacing: f32) -> f32 {
    let coord = x / spacing;
    let width = fwidth(coord);
    let g = abs(fract(coord - 0.5) - 0.5) / max(width, vec2(1e-6));
    let density = 1.0 - smoothstep(0.1, 0.25, max(width.x, width.y));
    return (1.0 - min(min(g.x, g.y), 1.0)) * density;
}

// Coverage of the line `x = 0`.
fn axis(x: f32) -> f32 {
    return 1.0 - min(abs(x) / max(fwidth(x) * 1.5, 1e-6), 1.0);
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    let wrapped = in.local + globals.grid.xy;
    let minor = lines(wrapped, globals.grid.z);
    let major = lines(wrapped, globals.grid.w);
    let world = in.local + globals.axes.xy;
    let x_axis = axis(world.y);
    let y_axis = axis(world.x);
    let fade = 1.0 - smoothstep(0.4, 1.0, length(in.local - globals.axes.zw) / globals.ground.z);
    let has_ground = globals.ground.y;
    var colour = vec4(0.035, 0.04, 0.045, 0.9 * has_ground);
    colour = mix(colour, vec4(0.12, 0.13, 0.15, 0.5), minor * 0.6);
    colour = mix(colour, vec4(0.22, 0.24, 0.27, 0.7), major);
    colour = mix(colour, vec4(0.85, 0.25, 0.2, 0.9), x_axis);
    colour = mix(colour, vec4(0.3, 0.8, 0.3, 0.9), y_axis);
    return vec4(colour.rgb, colour.a * fade);
}
