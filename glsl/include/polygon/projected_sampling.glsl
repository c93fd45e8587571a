// Projected-solid-angle sampling (Algorithm 4) and its density.
// Part of polygon.glsl, which includes its parts in order (each uses only those before it).
// Rust twin: `src/shading/polygon/projected_sampling.rs`; `tests/polygon_gpu.rs` checks that the two agree.

// Whether the state is central (the polygon contains the zenith).
bool is_central(ProjectedSolidAngleSampler state) {
    return !is_inner(state.inner_ellipse_0);
}

// Swaps sector boundaries lhs and rhs (with their ellipses) when rhs is clockwise of lhs; on a
// tie a degenerate ellipse goes first (A.2, rule 3).
void compare_and_swap(inout ProjectedSolidAngleSampler state, int lhs, int rhs) {
    float det = det2(state.sector_dirs[lhs], state.sector_dirs[rhs]);
    bool swap = det < 0.0
        || (det == 0.0 && is_degenerate(state.ellipses[rhs]) && !is_degenerate(state.ellipses[lhs]));
    if (swap) {
        vec2 dir = state.sector_dirs[lhs];
        state.sector_dirs[lhs] = state.sector_dirs[rhs];
        state.sector_dirs[rhs] = dir;
        vec2 ellipse = state.ellipses[lhs];
        state.ellipses[lhs] = state.ellipses[rhs];
        state.ellipses[rhs] = ellipse;
    }
}

// Prepares projected-solid-angle sampling of a polygon clipped to the horizon (the first half of
// Algorithm 4); either winding.
precise ProjectedSolidAngleSampler prepare_projected_solid_angle(Polygon clipped) {
    ProjectedSolidAngleSampler state = projected_solid_angle_sampler_empty();
    int count = clipped.count;
    precise float signed_angle = signed_projected_solid_angle(clipped);
    if (count < 3 || signed_angle == 0.0 || !polygon_is_finite(signed_angle)) {
        return state;
    }
    // Counterclockwise about +z
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        if (j >= count) {
            break;
        }
        state.vertices[j] = clipped.vertices[signed_angle > 0.0 ? j : count - 1 - j];
        state.sector_dirs[j] = state.vertices[j].xy;
    }
    // Associate vertices with ellipses (Algorithm 4)
    vec2 ellipse_0 = ellipse_from_edge(state.vertices[0], state.vertices[1]);
    vec2 previous = ellipse_0;
    for (int j = 1; j < MAX_CLIPPED_VERTICES; ++j) {
        if (j >= count) {
            break;
        }
        vec2 current = ellipse_from_edge(state.vertices[j], state.vertices[next_index(j, count)]);
        state.ellipses[j] = is_inner(current) ? previous : current;
        if (is_inner(previous) && !is_inner(current)) {
            state.inner_ellipse_0 = previous;
        }
        previous = current;
    }
    state.ellipses[0] = is_inner(ellipse_0) ? previous : ellipse_0;
    if (is_inner(previous) && !is_inner(ellipse_0)) {
        state.inner_ellipse_0 = previous;
    }
    // Projected solid angle per sector
    precise float total = 0.0;
    if (is_central(state)) {
        for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
            if (j >= count) {
                break;
            }
            vec2 ellipse = state.ellipses[j];
            precise float area = ellipse_area_in_sector(ellipse, ellipse_rsqrt_det(ellipse), state.sector_dirs[j],
                                                        state.sector_dirs[next_index(j, count)]);
            state.sector_areas[j] = area;
            total += area;
        }
    } else {
        // Odd-even transposition sort: `count` passes sort `count` elements
        for (int pass = 0; pass < MAX_CLIPPED_VERTICES; ++pass) {
            if (pass >= count) {
                break;
            }
            for (int k = 0; k < MAX_CLIPPED_VERTICES / 2; ++k) {
                int lhs = 2 * k + (pass & 1);
                if (lhs + 1 < count) {
                    compare_and_swap(state, lhs, lhs + 1);
                }
            }
        }
        vec2 inner = state.inner_ellipse_0;
        vec2 outer = state.ellipses[0];
        for (int j = 0; j < MAX_CLIPPED_VERTICES - 1; ++j) {
            if (j + 1 >= count) {
                break;
            }
            if (j > 0) {
                vec2 ellipse = state.ellipses[j];
                if (is_inner(ellipse)) {
                    inner = ellipse;
                } else {
                    outer = ellipse;
                }
            }
            // Near-degenerate ellipses bound sectors too thin to sample in f32
            bool steep = max(dot2(inner, inner), dot2(outer, outer)) > STEEP_ELLIPSE_SQUARED;
            precise float area = steep ? 0.0
                : area_between_ellipses_in_sector(inner, outer, state.sector_dirs[j], state.sector_dirs[j + 1]);
            state.sector_areas[j] = area;
            total += area;
        }
    }
    if (!is_central(state) && total <= 0.0) {
        // Rounding swamped every sector area: select sectors by their angle instead
        state.proxy_sector_areas = true;
        total = 0.0;
        for (int j = 0; j < MAX_CLIPPED_VERTICES - 1; ++j) {
            if (j + 1 >= count) {
                break;
            }
            precise float angle = det2(normalize2(state.sector_dirs[j]), normalize2(state.sector_dirs[j + 1]));
            state.sector_areas[j] = max(angle, 0.0);
            total += state.sector_areas[j];
        }
    }
    if (!(total > 0.0 && polygon_is_finite(total))) {
        return projected_solid_angle_sampler_empty();
    }
    state.count = count;
    state.sector_total = total;
    state.projected_solid_angle = abs(signed_angle);
    return state;
}

// Samples a direction uniformly with respect to projected solid angle within the polygon from
// u in [0, 1)^2 (the second half of Algorithm 4). Returns the unit direction in xyz and its
// density with respect to projected solid angle in w; an empty state returns (+z, 0).
precise vec4 sample_projected_solid_angle(ProjectedSolidAngleSampler state, vec2 u) {
    if (state.count == 0) {
        return vec4(0.0, 0.0, 1.0, 0.0);
    }
    int count = state.count;
    precise float target = u.x * state.sector_total;
    // Select the sector; a target beyond the last non-empty sector clamps to its end
    precise float selected_area = 0.0;
    precise float selected_target = 0.0;
    vec2 dir_0 = vec2(1.0, 0.0);
    vec2 dir_1 = vec2(0.0, 1.0);
    vec2 inner = state.inner_ellipse_0;
    vec2 outer = state.ellipses[0];
    vec2 selected_inner = inner;
    vec2 selected_outer = outer;
    bool central = is_central(state);
    int sector_count = central ? count : count - 1;
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        if (j >= sector_count) {
            break;
        }
        vec2 ellipse = state.ellipses[j];
        if (central || j == 0) {
            outer = ellipse;
        } else if (is_inner(ellipse)) {
            inner = ellipse;
        } else {
            outer = ellipse;
        }
        float area = state.sector_areas[j];
        if (area > 0.0) {
            selected_area = area;
            selected_target = min(target, area);
            selected_inner = inner;
            selected_outer = outer;
            dir_0 = state.sector_dirs[j];
            dir_1 = state.sector_dirs[next_index(j, count)];
        }
        if (target < area) {
            break;
        }
        target -= area;
    }
    precise vec2 w;
    if (central) {
        // Rotate s_0 within the ellipse by the angle 2 sqrt(det C) area
        precise float sqrt_det = sqrt(1.0 + dot2(selected_outer, selected_outer));
        precise float angle = 2.0 * selected_target * sqrt_det;
        precise vec2 direction =
            (cos(angle) * sqrt_det) * dir_0 + sin(angle) * rotate_90(ellipse_transform(selected_outer, dir_0));
        // Uniform in squared radius inside the ellipse
        w = direction * sqrt(max(u.y / ellipse_quadratic_form(selected_outer, direction), 0.0));
    } else {
        vec2 sector_u = vec2(min(selected_target / selected_area, 1.0), u.y);
        w = sample_sector_between_ellipses(sector_u, selected_target, selected_inner, selected_outer, dir_0, dir_1,
                                           !state.proxy_sector_areas);
    }
    precise float z = sqrt(max(1.0 - dot2(w, w), 0.0));
    return vec4(w, z, 1.0 / state.projected_solid_angle);
}

// Whether the unit direction lies in the convex spherical polygon (winding `orientation` = +-1),
// up to INSIDE_TOLERANCE radians.
precise bool is_inside(vec3 vertices[MAX_CLIPPED_VERTICES], int count, float orientation, vec3 direction) {
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        if (j >= count) {
            break;
        }
        precise vec3 normal = cross_stable(vertices[j], vertices[next_index(j, count)]) * orientation;
        if (polygon_dot3(normal, direction) < -INSIDE_TOLERANCE * length3(normal)) {
            return false;
        }
    }
    return true;
}

// The density with respect to projected solid angle of sample_projected_solid_angle at the unit
// direction: 1 / projected solid angle inside the clipped polygon, 0 elsewhere.
precise float projected_solid_angle_density(ProjectedSolidAngleSampler state, vec3 direction) {
    if (state.count == 0 || direction.z <= 0.0 || !is_inside(state.vertices, state.count, 1.0, direction)) {
        return 0.0;
    }
    return 1.0 / state.projected_solid_angle;
}
