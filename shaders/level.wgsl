// Level surfaces (meshes and heightfields): opaque triangles with one normal per face, lit as
// the solid spheres are (the sun from above and behind the viewer, a sky term, no highlight).
// The contact is two-sided, so a face seen from behind is lit as its other side.

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) eye: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) colour: vec4<f32>,
};

@vertex
fn vs_main(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) colour: vec4<f32>,
) -> VsOut {
    var out: VsOut;
    let eye = globals.view * vec4(position, 1.0);
    out.clip = globals.proj * eye;
    out.eye = eye.xyz;
    out.normal = (globals.view * vec4(normal, 0.0)).xyz;
    out.colour = decode(colour);
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    var n = normalize(in.normal);
    // The side facing the eye (view space: the eye is at the origin).
    if (dot(n, in.eye) > 0.0) {
        n = -n;
    }
    let l = globals.light.xyz;
    let diffuse = max(dot(n, l), 0.0);
    let sky = 0.5 + 0.5 * dot(n, (globals.view * vec4(0.0, 0.0, 1.0, 0.0)).xyz);
    let lit = in.colour.rgb * (0.18 + 0.12 * sky + 0.7 * diffuse);
    return vec4(lit, 1.0);
}
