// Clipping a polygon to the horizon (supplement A.1).
// Part of polygon.glsl, which includes its parts in order (each uses only those before it).
// Rust twin: `src/shading/polygon/clip.rs`; `tests/polygon_gpu.rs` checks that the two agree.

// Clips a convex polygon (3 to MAX_POLYGON_VERTICES vertices) to z >= 0 (supplement A.1).
precise Polygon clip_to_horizon(Polygon polygon) {
    Polygon clipped = polygon_empty();
    int count = polygon.count;
    if (count < 3 || count > MAX_CLIPPED_VERTICES) {
        return clipped;
    }
    int out_count = 0;
    bool overflow = false;
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        if (j >= count) {
            break;
        }
        vec3 a = polygon.vertices[j];
        vec3 b = polygon.vertices[next_index(j, count)];
        if (a.z >= 0.0) {
            if (out_count < MAX_CLIPPED_VERTICES) {
                clipped.vertices[out_count] = a;
                out_count += 1;
            } else {
                overflow = true;
            }
        }
        if ((a.z > 0.0 && b.z < 0.0) || (a.z < 0.0 && b.z > 0.0)) {
            // (p.xy q.z - q.xy p.z) / (q.z - p.z) with p above and q below
            vec3 p = a.z > 0.0 ? a : b;
            vec3 q = a.z > 0.0 ? b : a;
            precise float inverse_height = 1.0 / (q.z - p.z);
            precise vec3 crossing = vec3(kahan(p.x, q.z, q.x, p.z) * inverse_height,
                                         kahan(p.y, q.z, q.y, p.z) * inverse_height, 0.0);
            if (out_count < MAX_CLIPPED_VERTICES) {
                clipped.vertices[out_count] = crossing;
                out_count += 1;
            } else {
                overflow = true;
            }
        }
    }
    clipped.count = out_count >= 3 && !overflow ? out_count : 0;
    return clipped;
}
