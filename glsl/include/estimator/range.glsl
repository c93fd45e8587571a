// The range class: a triangle whose shading provably varies by at most ε over it needs level 1
// and no estimate (range_bound, range_proves). The derivation is in the twin's docs.
// Twin: `src/shading/estimator/range.rs`; proven equal with the rest of the estimator by
// `tests/multirate.rs` (`control_stage_levels_equal_the_twin`).
// A part of estimator.glsl, which includes the parts in dependency order: include that
// header, not this file.

// Taken from every lower bound on a cosine and added to every upper bound.
const float COS_PAD = 4.0e-6;
// The relative rounding allowed for the shading.
const float RANGE_RELATIVE_PAD = 1.0e-4;

// Every direction of a field is within the angle acos(cos) (below 90°) of axis, sin that angle's
// sine; ok false: no such spread.
struct Spread {
    vec3 axis;
    float cos;
    float sin;
    bool ok;
};

const Spread NO_SPREAD = Spread(vec3(0.0), 0.0, 0.0, false);

P float sine_of(float c) {
    P float s = sqrt(rmax(1.0 - c * c, 0.0));
    return s;
}

Spread new_spread(vec3 axis, float c) {
    return Spread(axis, c, sine_of(c), true);
}

// The spread of a field from its corners' directions (see `spread_of_units`).
Spread spread_of_units(vec3 u0, vec3 u1, vec3 u2) {
    if (is_zero(u0) || is_zero(u1) || is_zero(u2)) {
        return NO_SPREAD;
    }
    P vec3 axis = unit(u0 + u1 + u2);
    if (is_zero(axis)) {
        return NO_SPREAD;
    }
    P float c = rmin(rmin(dot3(axis, u0), dot3(axis, u1)), dot3(axis, u2)) - COS_PAD;
    if (!(c > 0.0)) {
        return NO_SPREAD;
    }
    return new_spread(axis, c);
}

// The spread of sum l_k w_k over the simplex (see `spread_of`).
Spread spread_of(vec3 w0, vec3 w1, vec3 w2) {
    return spread_of_units(unit(w0), unit(w1), unit(w2));
}

// The spread s of the directions from the triangle (p0, p1, p2) to eye_ball.xyz, widened to hold
// for every eye within eye_ball.w of it (see `widened` in Rust).
Spread widened(Spread s, vec3 p0, vec3 p1, vec3 p2, vec4 eye_ball) {
    if (!(eye_ball.w > 0.0)) {
        return s;
    }
    P float nearest = rmin(rmin(len(eye_ball.xyz - p0), len(eye_ball.xyz - p1)), len(eye_ball.xyz - p2));
    P float longest = rmax(rmax(len(p1 - p0), len(p2 - p1)), len(p0 - p2));
    P float turn = ball_angle(eye_ball.w, nearest - longest);
    if (!(turn < HALF_PI)) {
        return NO_SPREAD;
    }
    P float c = s.cos * est_cos(turn) - s.sin * est_sin(turn);
    if (!(c > 0.0)) {
        return NO_SPREAD;
    }
    return new_spread(s.axis, c);
}

// Lower and upper bounds on x.y for x within spread a and y within b (see `cosine_bounds`).
P vec2 cosine_bounds(Spread a, Spread b) {
    P float ct = clamp(dot3(a.axis, b.axis), -1.0, 1.0);
    P float st = sine_of(ct);
    P float sa = a.sin;
    P float sb = b.sin;
    P float cg = a.cos * b.cos - sa * sb;
    P float sg = sa * b.cos + a.cos * sb;
    P float hi = ct >= cg ? 1.0 : ct * cg + st * sg + COS_PAD;
    P float lo = ct <= -cg ? -1.0 : ct * cg - st * sg - COS_PAD;
    return vec2(lo, hi);
}

// The spread of the half vector of l and v, and a lower bound on v.h (see `half_spread`).
Spread half_spread(Spread l, Spread v, out float vh_lo) {
    vh_lo = 0.0;
    P vec3 w0 = l.axis + v.axis;
    P float w_length = len(w0);
    P float chord = sqrt(rmax(2.0 - 2.0 * l.cos, 0.0)) + sqrt(rmax(2.0 - 2.0 * v.cos, 0.0));
    if (!(chord < w_length)) {
        return NO_SPREAD;
    }
    P float sine = chord / w_length;
    P float c = sqrt(1.0 - sine * sine) - COS_PAD;
    P vec3 axis = unit(w0);
    if (!(c > 0.0) || is_zero(axis)) {
        return NO_SPREAD;
    }
    vh_lo = 0.5 * (w_length - chord);
    return new_spread(axis, c);
}

// One light's direction spread over the triangle and its least and largest irradiance scale
// (see `light_spread`): a point light at `position`, or a directional light travelling along it.
Spread light_spread(vec3 position, bool point, vec3 p0, vec3 p1, vec3 p2, out vec2 scale) {
    scale = vec2(1.0);
    if (!point) {
        P vec3 axis = unit(-position);
        if (is_zero(axis)) {
            return NO_SPREAD;
        }
        return new_spread(axis, 1.0 - COS_PAD);
    }
    P vec3 t0 = position - p0;
    P vec3 t1 = position - p1;
    P vec3 t2 = position - p2;
    Spread s = spread_of(t0, t1, t2);
    if (!s.ok) {
        return NO_SPREAD;
    }
    P float near = rmin(rmin(dot3(s.axis, t0), dot3(s.axis, t1)), dot3(s.axis, t2));
    P float far2 = rmax(rmax(len2(t0), len2(t1)), len2(t2)) * (1.0 + RANGE_RELATIVE_PAD);
    P float near2 = near * near * (1.0 - RANGE_RELATIVE_PAD);
    if (!(near > 0.0 && near2 >= MIN_LIGHT_DISTANCE_SQUARED && far2 <= 3.4028235e38)) {
        return NO_SPREAD;
    }
    P vec2 r = vec2(1.0 / far2, 1.0 / near2);
    scale = r;
    return s;
}

// The upper bound, per channel, of one light's specular part (see `specular_sup`); ok false:
// none.
P vec3 specular_sup(GpuMaterial material, vec2 param, Spread n, Spread l, Spread v, float nl_hi, out bool ok) {
    ok = true;
    if (MATERIAL_KIND == MATERIAL_LAMBERT) {
        return vec3(0.0);
    }
    ok = false;
    if (!v.ok) {
        return vec3(0.0);
    }
    float vh_lo;
    Spread h = half_spread(l, v, vh_lo);
    if (!h.ok) {
        return vec3(0.0);
    }
    P float nh_hi = clamp(cosine_bounds(n, h).y, 0.0, 1.0);
    if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
        ok = true;
        P vec3 s = material.specular.rgb * est_pow(nh_hi, param.x);
        return s;
    }
    if (param.x != param.y) {
        return vec3(0.0);
    }
    P float alpha = rmax(param.x * param.x, GGX_MIN_ALPHA);
    P float a2 = alpha * alpha;
    P float sin2 = rmax(1.0 - nh_hi * nh_hi, 0.0);
    P float d = sin2 * (1.0 - a2) + a2;
    P float distribution = a2 / (EXACT_PI * d * d);
    P float m = 1.0 - clamp(vh_lo, 0.0, 1.0);
    P float m2 = m * m;
    P vec3 f0 = material.specular.rgb;
    P vec3 fresnel = f0 + (vec3(1.0) - f0) * (m2 * m2 * m);
    P float k = 0.5 * alpha;
    P float nv_lo = rmax(cosine_bounds(n, v).x, 0.0);
    P float nl = clamp(nl_hi, 0.0, 1.0);
    P float visibility = nl / ((nl * (1.0 - k) + k) * (nv_lo * (1.0 - k) + k));
    ok = true;
    P vec3 s = fresnel * (distribution * visibility * 0.25);
    return s;
}

// What the specular shortcut needs of a triangle (`SpecularCaps` in Rust): the spreads of its
// normal and view; ok false for a material without a specular part or a spread of 90° or more.
struct SpecularCaps {
    Spread n;
    Spread v;
    bool ok;
};

// For a child's values (add_light's ADD_VALUES), which take no caps.
const SpecularCaps NO_SPECULAR_CAPS = SpecularCaps(NO_SPREAD, NO_SPREAD, false);

// The caps' spreads of the triangle of `frame` from its unit normals and unit vectors to the eye,
// for every eye of its ball (see `SpecularCaps::new`).
SpecularCaps specular_caps(Frame frame) {
    SpecularCaps caps = NO_SPECULAR_CAPS;
    if (MATERIAL_KIND == MATERIAL_LAMBERT) {
        return caps;
    }
    caps.n = spread_of_units(frame.unit_normals[0], frame.unit_normals[1], frame.unit_normals[2]);
    if (!caps.n.ok) {
        return caps;
    }
    caps.v = spread_of_units(frame.v_units[0], frame.v_units[1], frame.v_units[2]);
    if (caps.v.ok) {
        caps.v = widened(caps.v, frame.vertices[0], frame.vertices[1], frame.vertices[2],
                         vec4(frame.eye, frame.eye_radius));
    }
    caps.ok = caps.v.ok;
    return caps;
}

// A light's specular part's upper bound radiance sup(specular) sup(E') (specular_most: the last
// two), padded for rounding: its cap (`padded_cap` in Rust).
P vec3 padded_cap(vec3 radiance, vec3 specular_most) {
    P vec3 cap = radiance * specular_most * (1.0 + RANGE_RELATIVE_PAD);
    return cap;
}

// The cap of a point or directional light's specular part over the triangle (p0, p1, p2)
// (`SpecularCaps::cap` in Rust; range_bound decides whether every light's is small enough); ok
// false where there is no bound.
P vec3 specular_cap(SpecularCaps caps, GpuMaterial material, vec2 param, bool point, vec3 position,
                    vec3 radiance, vec3 p0, vec3 p1, vec3 p2, out bool ok) {
    ok = false;
    vec2 scale;
    Spread l = light_spread(position, point, p0, p1, p2, scale);
    if (!l.ok) {
        return vec3(0.0);
    }
    P float nl_hi = cosine_bounds(caps.n, l).y;
    if (!(nl_hi > 0.0)) {
        ok = true;
        return vec3(0.0);
    }
    bool has_specular;
    P vec3 specular = specular_sup(material, param, caps.n, l, caps.v, nl_hi, has_specular);
    if (!has_specular) {
        return vec3(0.0);
    }
    ok = true;
    return padded_cap(radiance, specular * scale.y);
}

// Whether every channel of range, padded for rounding, is at most eps (see `within`).
bool range_within(vec3 range, float eps) {
    P vec3 padded = range * (1.0 + RANGE_RELATIVE_PAD) + 1.0e-6;
    return padded.x <= eps && padded.y <= eps && padded.z <= eps;
}

// An upper bound, per channel, on the shading's range over the triangle (`RangeClass::bound` in
// Rust), returned as soon as the lights summed so far cannot prove level 1 for `eps` and a light's
// specular part is not capped; ok false: none (a polygonal light, a varying GGX roughness, a
// spread of 90° or more). `every_capped`: whether every light's specular part is within its cap
// (`RangeClass::every_specular_capped`; specular_cap from the same quantities). The lights that
// reach none of the triangle by its visibility `classes` (shadowed_in) are not among them.
P vec3 range_bound(vec3 p0, vec3 p1, vec3 p2, vec3 n0, vec3 n1, vec3 n2, vec4 eye_ball, GpuMaterial material,
                   vec2 param, float eps, uint classes, out bool ok, out bool every_capped) {
    ok = false;
    every_capped = false;
    if (POLYGON_LIGHT_COUNT > 0) {
        return vec3(0.0);
    }
    Spread n = spread_of(n0, n1, n2);
    if (!n.ok) {
        return vec3(0.0);
    }
    // The view's spread matters to the specular parts only.
    Spread v = Spread(vec3(0.0), 0.0, 0.0, false);
    if (MATERIAL_KIND != MATERIAL_LAMBERT) {
        v = spread_of(eye_ball.xyz - p0, eye_ball.xyz - p1, eye_ball.xyz - p2);
        if (v.ok) {
            v = widened(v, p0, p1, p2, eye_ball);
        }
    }
    bool capped = MATERIAL_KIND != MATERIAL_LAMBERT && v.ok;
    P float budget = eps * SPECULAR_CAP_SHARE;
    P float count = float(POINT_LIGHT_COUNT + DIRECTIONAL_LIGHT_COUNT + POLYGON_LIGHT_COUNT - shadowed_count(classes));
    P vec3 kd = material.diffuse.rgb;
    P vec3 total = vec3(0.0);
    for (int i = 0; i < POINT_LIGHT_COUNT + DIRECTIONAL_LIGHT_COUNT; ++i) {
        if (shadowed_in(i, classes)) {
            continue;
        }
        vec2 scale;
        Spread l = light_spread(lights[i].position.xyz, i < POINT_LIGHT_COUNT, p0, p1, p2, scale);
        if (!l.ok) {
            return vec3(0.0);
        }
        P vec2 nl = cosine_bounds(n, l);
        if (!(nl.y > 0.0)) {
            continue;
        }
        P vec3 diffuse = kd * (scale.y * nl.y - scale.x * rmax(nl.x, 0.0));
        bool has_specular;
        P vec3 specular = specular_sup(material, param, n, l, v, nl.y, has_specular);
        if (!has_specular) {
            return vec3(0.0);
        }
        P vec3 radiance = lights[i].radiance.rgb;
        P vec3 specular_most = specular * scale.y;
        total = total + radiance * (diffuse + specular_most);
        capped = capped && max_el(padded_cap(radiance, specular_most)) * count <= budget;
        if (!range_within(total, eps) && !capped) {
            ok = true;
            return total;
        }
    }
    ok = true;
    every_capped = capped;
    return total;
}

// Whether the range class proves level 1 for eps (see `range_proves`).
bool range_proves(vec3 range, bool ok, float eps) {
    return ok && range_within(range, eps);
}

// Whether the triangle is settled by the range class (level 1, no estimate) for every eye within
// eye_ball.w of eye_ball.xyz, as estimate_pass's callers decide it (`estimate_textured` in Rust);
// `every_capped`: whether the estimate bounds every light's specular part by its cap (see
// range_bound). `classes`: the triangle's visibility classes (estimated_classes).
bool settled_by_range(vec3 p0, vec3 p1, vec3 p2, vec3 n0, vec3 n1, vec3 n2, vec4 eye_ball, uint material_index,
                      vec2 param, float epsilon, uint classes, out bool every_capped) {
    P float eps = epsilon > 0.0 ? epsilon : 0.0;
    bool ok;
    P vec3 range = range_bound(p0, p1, p2, n0, n1, n2, eye_ball, materials[material_index], param, eps, classes, ok,
                                every_capped);
    return range_proves(range, ok, eps);
}
