// Shading with a polygonal area light at one point: the exact diffuse part (closed-form projected
// solid angle of the polygon clipped to the horizon) and the specular part by light and BRDF
// samples under clamped optimal MIS. Rust twin: `src/shading/polygon_light.rs`, whose header gives
// the estimator, the sample set and the MIS coefficients. Included by brdf.glsl, after
// `reflect_one_light`, which supplies the specular integrand.
#ifndef POLYGON_LIGHT_GLSL
#define POLYGON_LIGHT_GLSL
#include "polygon.glsl"

#define POLYGON_SAMPLING_PROJECTED 0
#define POLYGON_SAMPLING_SOLID 1

// An orthonormal basis (t, b) completing the unit n, (t, b, n) right-handed (Duff et al. 2017).
void tangent_frame(vec3 n, out vec3 t, out vec3 b) {
    float sign_z = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (sign_z + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + sign_z * n.x * n.x * a, sign_z * c, -sign_z * n.x);
    b = vec3(c, sign_z + n.y * n.y * a, -n.y);
}

// The specular integrand per unit radiance in the local frame (n = +z).
vec3 polygon_specular(vec3 l, vec3 v, GpuMaterial m, float parameter) {
    return reflect_one_light(vec3(0.0, 0.0, 1.0), l, v, m, parameter).specular;
}

// The density with respect to solid angle with which `sample_brdf` produces l.
float brdf_density(vec3 l, vec3 v, float parameter) {
    vec3 h = safe_normalize(l + v);
    float n_dot_h = h.z;
    float v_dot_h = dot(v, h);
    if (n_dot_h <= 0.0 || v_dot_h <= 0.0) {
        return 0.0;
    }
    float half_density = 0.0;
    if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
        half_density = (parameter + 1.0) / (2.0 * PI) * pow(n_dot_h, parameter);
    } else if (MATERIAL_KIND == MATERIAL_GGX) {
        half_density = ggx_d(n_dot_h, max(parameter * parameter, GGX_MIN_ALPHA)) * n_dot_h;
    }
    return half_density / (4.0 * v_dot_h);
}

// The BRDF technique: xyz the direction, w its density (Blinn-Phong h ~ (n.h)^s, GGX h ~ D n.h).
vec4 sample_brdf(vec2 u, vec3 v, float parameter) {
    float cos_theta = 1.0;
    if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
        cos_theta = pow(u.x, 1.0 / (parameter + 1.0));
    } else if (MATERIAL_KIND == MATERIAL_GGX) {
        float alpha = max(parameter * parameter, GGX_MIN_ALPHA);
        float a2 = alpha * alpha;
        cos_theta = sqrt(max((1.0 - u.x) / (1.0 + (a2 - 1.0) * u.x), 0.0));
    } else {
        return vec4(0.0, 0.0, 1.0, 0.0);
    }
    float sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    float phi = 2.0 * PI * u.y;
    vec3 h = vec3(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
    vec3 l = h * (2.0 * dot(v, h)) - v;
    return vec4(l, brdf_density(l, v, parameter));
}

// The light technique's density with respect to solid angle at w.
float light_density(ProjectedSolidAngleSampler psa, SolidAngleSampler sa, vec3 w) {
    if (POLYGON_TECHNIQUE == POLYGON_SAMPLING_PROJECTED) {
        return projected_to_solid_angle_density(projected_solid_angle_density(psa, w), w);
    }
    return solid_angle_density(sa, w);
}

// f/p where p > 0, else 0.
vec3 polygon_ratio(vec3 f, float p) {
    return p > 0.0 ? f / p : vec3(0.0);
}

// Light `index`'s contribution at `position` (unit normal n, unit direction to the eye v): the
// diffuse part kd L (projected solid angle) and the sampled specular part.
Shading shade_polygon(vec3 position, vec3 n, vec3 v, GpuMaterial m, float parameter, int index) {
    GpuPolygonLight light = polygon_lights[index];
    Shading s = Shading(vec3(0.0), vec3(0.0));
    // One-sided: only points in front of the emitter's plane see it.
    if (dot(light.normal.xyz, position - light.vertices[0].xyz) <= 0.0) {
        return s;
    }
    vec3 t;
    vec3 b;
    tangent_frame(n, t, b);
    Polygon polygon = polygon_empty();
    int count = light.info.x;
    for (int j = 0; j < MAX_POLYGON_VERTICES; ++j) {
        if (j < count) {
            vec3 w = light.vertices[j].xyz - position;
            polygon.vertices[j] = vec3(dot(w, t), dot(w, b), dot(w, n));
        }
    }
    polygon.count = count;
    Polygon clipped = clip_to_horizon(polygon);
    ProjectedSolidAngleSampler psa = projected_solid_angle_sampler_empty();
    SolidAngleSampler sa = solid_angle_sampler_empty();
    float projected;
    if (POLYGON_TECHNIQUE == POLYGON_SAMPLING_PROJECTED) {
        psa = prepare_projected_solid_angle(clipped);
        projected = psa.projected_solid_angle;
    } else {
        sa = prepare_solid_angle(clipped);
        projected = projected_solid_angle(clipped);
    }
    vec3 radiance = light.radiance.rgb;
    s.diffuse = m.diffuse.rgb * radiance * projected;
    if (MATERIAL_KIND == MATERIAL_LAMBERT || !(projected > 0.0)) {
        return s;
    }

    vec3 v_local = vec3(dot(v, t), dot(v, b), dot(v, n));
    // The MIS coefficients: each technique's one-sample estimate at its most likely direction.
    vec3 centre = vec3(0.0);
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        if (j < clipped.count) {
            centre += safe_normalize(clipped.vertices[j]);
        }
    }
    centre = safe_normalize(centre);
    vec3 f_centre = polygon_ratio(polygon_specular(centre, v_local, m, parameter), light_density(psa, sa, centre));
    vec3 mirror = vec3(-v_local.x, -v_local.y, v_local.z);
    vec3 f_mirror =
        polygon_ratio(polygon_specular(mirror, v_local, m, parameter), brdf_density(mirror, v_local, parameter));
    vec2 coefficients = vec2(max(max(f_centre.x, f_centre.y), f_centre.z),
                             max(max(f_mirror.x, f_mirror.y), f_mirror.z));

    vec3 sum = vec3(0.0);
    uint samples = uint(max(POLYGON_SAMPLES, 1));
    for (uint i = 0u; i < samples; ++i) {
        vec2 u = sample_point(i, samples);
        vec4 light_sample;
        if (POLYGON_TECHNIQUE == POLYGON_SAMPLING_PROJECTED) {
            light_sample = sample_projected_solid_angle(psa, u);
            light_sample.w = projected_to_solid_angle_density(light_sample.w, light_sample.xyz);
        } else {
            light_sample = sample_solid_angle(sa, u);
        }
        if (light_sample.w > 0.0 && light_sample.z > 0.0) {
            float p_brdf = brdf_density(light_sample.xyz, v_local, parameter);
            vec2 w = clamped_optimal_mis_weights(vec2(light_sample.w, p_brdf), coefficients, MIS_VISIBILITY);
            sum += polygon_specular(light_sample.xyz, v_local, m, parameter) * (w.x / light_sample.w);
        }
        vec4 brdf_sample = sample_brdf(u.yx, v_local, parameter);
        if (brdf_sample.w > 0.0 && brdf_sample.z > 0.0) {
            float p_light = light_density(psa, sa, brdf_sample.xyz);
            if (p_light > 0.0) {
                vec2 w = clamped_optimal_mis_weights(vec2(p_light, brdf_sample.w), coefficients, MIS_VISIBILITY);
                sum += polygon_specular(brdf_sample.xyz, v_local, m, parameter) * (w.y / brdf_sample.w);
            }
        }
    }
    s.specular = sum * radiance * (1.0 / float(samples));
    return s;
}

#endif
