// Analytic screen-space derivatives of vertex attributes (seed 002, Chao Jia): perspective-correct
// barycentrics at a pixel and their derivatives per pixel step, attributes interpolated with
// them, and Vulkan's isotropic texture LOD. For shaders without hardware derivatives (the
// tessellation stages, a visibility buffer).
// Rust twin: `src/shading/derivatives.rs`, which also has the derivation. Keep the two in step,
// operation for operation; `precise` keeps the driver from fusing multiply-adds the Rust twin
// does not fuse.
//
// Conventions: Vulkan clip space, NDC = clip.xyz / w; framebuffer pixel from the top-left corner,
// pixel centres at +0.5, ndc = 2 * pixel / viewport - 1 (positive viewport height).
#ifndef DERIVATIVES_GLSL
#define DERIVATIVES_GLSL

// Perspective-correct barycentrics of a pixel and their derivatives per pixel step in x and y
// (the components of ddx and of ddy each sum to zero).
struct BarycentricDerivatives {
    vec3 lambda;
    vec3 ddx;
    vec3 ddy;
};

// The smallest texel footprint texture_lod takes the logarithm of, 2^-100: zero derivatives
// give LOD -100 rather than -inf.
const float MIN_FOOTPRINT = 7.888609e-31;

// What barycentric_derivatives returns for degenerate input: the centroid, no change.
BarycentricDerivatives degenerate_barycentric_derivatives() {
    return BarycentricDerivatives(vec3(1.0 / 3.0), vec3(0.0), vec3(0.0));
}

float derivatives_cross2(vec2 a, vec2 b) {
    precise float c = a.x * b.y - b.x * a.y;
    return c;
}

bool derivatives_finite(vec3 v) {
    return !any(isnan(v)) && !any(isinf(v));
}

// Perspective-correct barycentrics at framebuffer position `pixel` of the triangle with clip-space
// vertices c0, c1, c2 on a viewport of `viewport` pixels, and their derivatives per pixel step.
// Degenerate input (a vertex with w <= 0, a projected triangle of zero area, a pixel on or beyond
// the triangle's horizon, any non-finite result) gives degenerate_barycentric_derivatives().
BarycentricDerivatives barycentric_derivatives(vec4 c0, vec4 c1, vec4 c2, vec2 pixel, vec2 viewport) {
    if (!(c0.w > 0.0 && c1.w > 0.0 && c2.w > 0.0)) {
        return degenerate_barycentric_derivatives();
    }
    precise vec3 inv_w = vec3(1.0 / c0.w, 1.0 / c1.w, 1.0 / c2.w);
    precise vec2 n0 = c0.xy * inv_w.x;
    precise vec2 n1 = c1.xy * inv_w.y;
    precise vec2 n2 = c2.xy * inv_w.z;
    precise vec2 p = 2.0 * pixel / viewport - 1.0;
    precise float inv_area = 1.0 / derivatives_cross2(n1 - n0, n2 - n0);
    precise vec2 a0 = n0 - p;
    precise vec2 a1 = n1 - p;
    precise vec2 a2 = n2 - p;
    precise vec3 lambda_n =
        vec3(derivatives_cross2(a1, a2), derivatives_cross2(a2, a0), derivatives_cross2(a0, a1)) * inv_area;
    precise vec3 dndx = vec3(n1.y - n2.y, n2.y - n0.y, n0.y - n1.y) * inv_area;
    precise vec3 dndy = vec3(n2.x - n1.x, n0.x - n2.x, n1.x - n0.x) * inv_area;
    precise vec3 q = lambda_n * inv_w;
    precise float inv_w_pixel = q.x + q.y + q.z;
    precise float w = 1.0 / inv_w_pixel;
    precise vec3 lambda = q * w;
    precise vec2 step = 2.0 / viewport;
    precise vec3 tx = dndx * inv_w * (w * step.x);
    precise vec3 ty = dndy * inv_w * (w * step.y);
    precise vec3 ddx = tx - lambda * (tx.x + tx.y + tx.z);
    precise vec3 ddy = ty - lambda * (ty.x + ty.y + ty.z);
    bool finite = derivatives_finite(lambda) && derivatives_finite(ddx) && derivatives_finite(ddy);
    if (!(inv_w_pixel > 0.0 && finite)) {
        return degenerate_barycentric_derivatives();
    }
    return BarycentricDerivatives(lambda, ddx, ddy);
}

// A 2-vector vertex attribute (uv) at the pixel, and its derivatives per pixel step.
void interpolate2(BarycentricDerivatives b, vec2 a0, vec2 a1, vec2 a2,
                  out vec2 value, out vec2 ddx, out vec2 ddy) {
    precise vec2 v = a0 * b.lambda.x + a1 * b.lambda.y + a2 * b.lambda.z;
    precise vec2 dx = a0 * b.ddx.x + a1 * b.ddx.y + a2 * b.ddx.z;
    precise vec2 dy = a0 * b.ddy.x + a1 * b.ddy.y + a2 * b.ddy.z;
    value = v;
    ddx = dx;
    ddy = dy;
}

// A 3-vector vertex attribute (position, normal) at the pixel, and its derivatives per pixel step.
void interpolate3(BarycentricDerivatives b, vec3 a0, vec3 a1, vec3 a2,
                  out vec3 value, out vec3 ddx, out vec3 ddy) {
    precise vec3 v = a0 * b.lambda.x + a1 * b.lambda.y + a2 * b.lambda.z;
    precise vec3 dx = a0 * b.ddx.x + a1 * b.ddx.y + a2 * b.ddx.z;
    precise vec3 dy = a0 * b.ddy.x + a1 * b.ddy.y + a2 * b.ddy.z;
    value = v;
    ddx = dx;
    ddy = dy;
}

// Vulkan's isotropic LOD for uv derivatives per pixel on a texture of texture_size texels:
// log2(max(|duv_dx * size|, |duv_dy * size|)), the footprint at least MIN_FOOTPRINT.
float texture_lod(vec2 duv_dx, vec2 duv_dy, vec2 texture_size) {
    float rho_x = length(duv_dx * texture_size);
    float rho_y = length(duv_dy * texture_size);
    return log2(max(max(rho_x, rho_y), MIN_FOOTPRINT));
}

#endif
