// Spheres as ray-cast impostors: one camera-facing quad per instance, all in one instanced draw.
// The fragment shader intersects the view ray with the exact sphere and writes its depth, so a
// sphere is round at any size and costs two triangles. `fs_solid` shades bodies (Lambert plus a
// highlight); `fs_ghost` draws the translucent rim of ghosts and targets.
// A sphere is drawn at least `globals.ground.w` pixels in radius, so a 5 cm ball stays visible
// from 100 m.

struct Instance {
    @location(0) center: vec3<f32>,
    @location(1) radius: f32,
    @location(2) colour: vec4<f32>,
};

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    // The quad point in view space: the ray from the eye (the origin) passes through it.
    @location(0) ray: vec3<f32>,
    @location(1) center: vec3<f32>,
    @location(2) radius: f32,
    @location(3) colour: vec4<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, inst: Instance) -> VsOut {
    var out: VsOut;
    let c = (globals.view * vec4(inst.center, 1.0)).xyz;
    let d = length(c);
    // World size of one pixel at this depth.
    let pixel = 2.0 * max(-c.z, 1e-6) / (globals.viewport.w * globals.proj[1][1]);
    let r = max(inst.radius, globals.ground.w * pixel);
    if (d <= r * 1.001 || -c.z <= 0.0) {
        out.clip = CULLED;
        return out;
    }
    // A square across the ray to the centre, wide enough to hold the sphere's silhouette: the
    // tangent cone of half-angle asin(r / d) cuts that plane in a circle of radius r d / sqrt(d^2 - r^2).
    let axis = c / d;
    var helper = vec3(0.0, 1.0, 0.0);
    if (abs(axis.y) > 0.99) {
        helper = vec3(1.0, 0.0, 0.0);
    }
    let right = normalize(cross(axis, helper));
    let up = cross(right, axis);
    let half = r * d / sqrt(d * d - r * r);
    let corner = vec2(f32(vi & 1u), f32((vi >> 1u) & 1u)) * 2.0 - 1.0;
    let p = c + half * (corner.x * right + corner.y * up);
    out.clip = globals.proj * vec4(p, 1.0);
    out.ray = p;
    out.center = c;
    out.radius = r;
    out.colour = decode(inst.colour);
    return out;
}

struct Hit {
    point: vec3<f32>,
    normal: vec3<f32>,
    dir: vec3<f32>,
};

// Ray from the eye through the fragment against the sphere; discards a miss.
fn intersect(in: VsOut) -> Hit {
    let dir = normalize(in.ray);
    let b = dot(dir, in.center);
    // Distance from the centre to the ray, formed without the cancellation of b^2 - |c|^2.
    let off = in.center - b * dir;
    let disc = in.radius * in.radius - dot(off, off);
    if (disc < 0.0) {
        discard;
    }
    let point = dir * (b - sqrt(disc));
    return Hit(point, (point - in.center) / in.radius, dir);
}

fn depth_of(p: vec3<f32>) -> f32 {
    let clip = globals.proj * vec4(p, 1.0);
    return clip.z / clip.w;
}

struct FragOut {
    @location(0) colour: vec4<f32>,
    @builtin(frag_depth) depth: f32,
};

@fragment
fn fs_solid(in: VsOut) -> FragOut {
    let hit = intersect(in);
    let l = globals.light.xyz;
    let diffuse = max(dot(hit.normal, l), 0.0);
    let sky = 0.5 + 0.5 * dot(hit.normal, (globals.view * vec4(0.0, 0.0, 1.0, 0.0)).xyz);
    let h = normalize(l - hit.dir);
    let highlight = pow(max(dot(hit.normal, h), 0.0), 40.0) * 0.35;
    let lit = in.colour.rgb * (0.18 + 0.12 * sky + 0.75 * diffuse) + vec3(highlight);
    return FragOut(vec4(lit, 1.0), depth_of(hit.point));
}

@fragment
fn fs_ghost(in: VsOut) -> FragOut {
    let hit = intersect(in);
    let facing = abs(dot(hit.normal, hit.dir));
    let rim = 0.3 + 0.7 * pow(1.0 - facing, 2.0);
    return FragOut(vec4(in.colour.rgb, in.colour.a * rim), depth_of(hit.point));
}
