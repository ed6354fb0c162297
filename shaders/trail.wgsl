// Trails from the ring of per-tick samples (see src/render/trails.rs): one instance per body
// slot, one line segment per pair of consecutive samples, newest first. The first point is the
// drawn (interpolated) position, mix(sample 1, sample 0, alpha), so the trail meets the sphere.
// Segments older than a slot's sample count collapse outside the clip volume.

struct Trail {
    colour: vec4<f32>,
    head: u32,
    len: u32,
    stride: u32,
    alpha: f32,
    // Segments drawn per trail (fewer when many bodies share the budget); the fade spans them.
    segments: u32,
};

@group(1) @binding(0) var<uniform> trail: Trail;
@group(1) @binding(1) var<storage, read> samples: array<vec4<f32>>;
@group(1) @binding(2) var<storage, read> counts: array<u32>;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec4<f32>,
};

fn sample_at(slot: u32, age: u32) -> vec3<f32> {
    let row = (trail.head + trail.len - age) % trail.len;
    return samples[row * trail.stride + slot].xyz;
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) slot: u32) -> VsOut {
    var out: VsOut;
    let segment = vi / 2u;
    let age = segment + (vi & 1u);
    if (segment + 1u >= counts[slot]) {
        out.clip = CULLED;
        return out;
    }
    var p = sample_at(slot, age);
    if (age == 0u) {
        p = mix(sample_at(slot, 1u), p, trail.alpha);
    }
    out.clip = globals.proj * globals.view * vec4(p, 1.0);
    let fade = 1.0 - f32(age) / f32(trail.segments + 1u);
    let c = decode(trail.colour);
    out.colour = vec4(c.rgb, c.a * fade * fade);
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    return in.colour;
}
