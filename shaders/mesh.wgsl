// geosnap's 3D view: shaded primitives and the ground grid.
//
// One vertex format for both: position, normal and colour. Triangles are lit by a key
// light from the camera's upper left, a hemisphere ambient (sky above, ground below) and
// a soft rim; lines (the grid, with a zero normal) are drawn unlit.

struct Uniforms {
    view_proj: mat4x4<f32>,
    // xyz: direction towards the key light, in model space.
    light: vec4<f32>,
    // xyz: the camera position, for the rim term.
    eye: vec4<f32>,
};

@group(0) @binding(0) var<uniform> u: Uniforms;

// Set where the target cannot be viewed as sRGB (GL without view formats): the shader
// then writes gamma-encoded bytes itself, which is what the UI reads either way.
override ENCODE_SRGB: bool = false;

fn shown(c: vec4<f32>) -> vec4<f32> {
    if (!ENCODE_SRGB) {
        return c;
    }
    let rgb = clamp(c.rgb, vec3<f32>(0.0), vec3<f32>(1.0));
    let low = rgb * 12.92;
    let high = 1.055 * pow(rgb, vec3<f32>(1.0 / 2.4)) - vec3<f32>(0.055);
    return vec4<f32>(select(high, low, rgb <= vec3<f32>(0.0031308)), c.a);
}

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) color: vec4<f32>,
    @location(2) world: vec3<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = u.view_proj * vec4<f32>(v.position, 1.0);
    out.normal = v.normal;
    out.color = v.color;
    out.world = v.position;
    return out;
}

@fragment
fn fs_main(v: VertexOut) -> @location(0) vec4<f32> {
    let len = length(v.normal);
    if (len < 0.5) {
        return shown(v.color);
    }
    let n = v.normal / len;
    let to_eye = normalize(u.eye.xyz - v.world);
    // Two-sided: a face seen from behind is lit as if it faced the camera.
    let facing = select(-n, n, dot(n, to_eye) >= 0.0);
    let key = max(dot(facing, normalize(u.light.xyz)), 0.0);
    let sky = 0.5 + 0.5 * facing.y;
    let ambient = mix(vec3<f32>(0.32, 0.30, 0.28), vec3<f32>(0.55, 0.58, 0.62), sky);
    let rim = pow(1.0 - max(dot(facing, to_eye), 0.0), 3.0) * 0.25;
    let half_vector = normalize(normalize(u.light.xyz) + to_eye);
    let specular = pow(max(dot(facing, half_vector), 0.0), 48.0) * 0.25;
    let lit = v.color.rgb * (ambient + 0.75 * key) + vec3<f32>(rim + specular);
    return shown(vec4<f32>(lit, v.color.a));
}
