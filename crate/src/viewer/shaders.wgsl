// deeprep viewer shaders: lit instanced meshes (joints, bones, dots, triangle
// meshes) and unlit colored lines (grid, hair strands). WebGL2-compatible:
// uniforms only, no storage buffers.

struct Globals {
    view_proj: mat4x4<f32>,
    light_dir: vec4<f32>,
};

@group(0) @binding(0) var<uniform> globals: Globals;

struct LitIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) m0: vec4<f32>,
    @location(3) m1: vec4<f32>,
    @location(4) m2: vec4<f32>,
    @location(5) m3: vec4<f32>,
    @location(6) color: vec4<f32>,
    @location(7) tint: vec4<f32>,
};

struct LitOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) color: vec4<f32>,
};

@vertex
fn vs_lit(v: LitIn) -> LitOut {
    let model = mat4x4<f32>(v.m0, v.m1, v.m2, v.m3);
    var out: LitOut;
    out.clip = globals.view_proj * model * vec4<f32>(v.position, 1.0);
    // Instances are rotation x non-uniform scale; the inverse-transpose of
    // the upper 3x3 keeps normals right.
    let m3 = mat3x3<f32>(model[0].xyz, model[1].xyz, model[2].xyz);
    let inv_sq = vec3<f32>(1.0 / max(dot(m3[0], m3[0]), 1e-12), 1.0 / max(dot(m3[1], m3[1]), 1e-12), 1.0 / max(dot(m3[2], m3[2]), 1e-12));
    out.normal = normalize(m3 * (v.normal * inv_sq));
    out.color = v.color * v.tint;
    return out;
}

@fragment
fn fs_lit(i: LitOut) -> @location(0) vec4<f32> {
    let n = normalize(i.normal);
    let l = normalize(globals.light_dir.xyz);
    let diffuse = max(dot(n, l), 0.0);
    let fill = max(dot(n, -l), 0.0) * 0.25;
    let shade = 0.3 + 0.7 * diffuse + fill;
    return vec4<f32>(i.color.rgb * shade, i.color.a);
}

struct LineIn {
    @location(0) position: vec3<f32>,
    @location(1) color: vec4<f32>,
};

struct LineOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
};

@vertex
fn vs_line(v: LineIn) -> LineOut {
    var out: LineOut;
    out.clip = globals.view_proj * vec4<f32>(v.position, 1.0);
    out.color = v.color;
    return out;
}

@fragment
fn fs_line(i: LineOut) -> @location(0) vec4<f32> {
    return i.color;
}
