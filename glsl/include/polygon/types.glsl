// The constants, the structs Polygon, ProjectedSolidAngleSampler and SolidAngleSampler, and
// their empty values.
// Part of polygon.glsl, which includes its parts in order (each uses only those before it).
// Rust twin: `src/shading/polygon/types.rs`; `tests/polygon_gpu.rs` checks that the two agree.

// Most vertices a light polygon may have.
const int MAX_POLYGON_VERTICES = 8;
// Most vertices a polygon clipped to the horizon may have.
const int MAX_CLIPPED_VERTICES = MAX_POLYGON_VERTICES + 1;
// Most triangles in the fan of a clipped polygon.
const int MAX_FAN_TRIANGLES = MAX_CLIPPED_VERTICES - 2;
// The visibility estimate v of clamped optimal MIS that the paper uses throughout (B.3).
const float DEFAULT_MIS_VISIBILITY = 0.5;
// f32::EPSILON and f32::MIN_POSITIVE.
const float POLYGON_EPSILON = 1.1920929e-7;
const float POLYGON_MIN_POSITIVE = 1.17549435e-38;
// A (projected) solid angle below this fraction of its terms' magnitude counts as zero.
const float EMPTY_RELATIVE_THRESHOLD = 32.0 * POLYGON_EPSILON;
// Directions this close (radians) outside an edge's great circle still count as inside.
const float INSIDE_TOLERANCE = 4.0 * POLYGON_EPSILON;
// Algorithm 3 skips the iteration this close to the ends of the sector.
const float ITERATION_MARGIN = 1.0e-5;
// |u|^2 above which an ellipse counts as nearly degenerate in the decentral case.
const float STEEP_ELLIPSE_SQUARED = 1.0e6;
// Iterations of Algorithm 3.
const int ITERATION_COUNT = 2;

// A convex planar polygon: only the first `count` vertices are meaningful; 0 means empty.
struct Polygon {
    vec3 vertices[MAX_CLIPPED_VERTICES];
    int count;
};

// Everything projected-solid-angle sampling needs (the first half of Algorithm 4).
struct ProjectedSolidAngleSampler {
    int count;                                   // 0 when there is nothing to sample
    vec3 vertices[MAX_CLIPPED_VERTICES];         // counterclockwise about +z
    vec2 sector_dirs[MAX_CLIPPED_VERTICES];      // sector boundary directions
    vec2 ellipses[MAX_CLIPPED_VERTICES];         // per boundary the next edge's ellipse
    vec2 inner_ellipse_0;                        // inner ellipse of the first sector, or (1, 0)
    float sector_areas[MAX_CLIPPED_VERTICES];    // projected solid angle per sector
    float sector_total;                          // sum of sector_areas
    bool proxy_sector_areas;                     // sector_areas hold angles instead
    float projected_solid_angle;                 // the closed form (normalises the density)
};

// Everything solid-angle sampling needs: the polygon as a triangle fan around vertex 0.
struct SolidAngleSampler {
    int count;                                   // 0 when there is nothing to sample
    vec3 directions[MAX_CLIPPED_VERTICES];       // unit directions to the vertices
    vec3 triangles[MAX_FAN_TRIANGLES];           // (G0, G1, G2) of Algorithm 5 per triangle
    float fan_solid_angles[MAX_FAN_TRIANGLES];   // solid angle of the fan up to triangle j
    float solid_angle;                           // total
    float orientation;                           // +-1 such that edges' normals point inwards
};

Polygon polygon_empty() {
    Polygon polygon;
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        polygon.vertices[j] = vec3(0.0);
    }
    polygon.count = 0;
    return polygon;
}

ProjectedSolidAngleSampler projected_solid_angle_sampler_empty() {
    ProjectedSolidAngleSampler state;
    state.count = 0;
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        state.vertices[j] = vec3(0.0);
        state.sector_dirs[j] = vec2(0.0);
        state.ellipses[j] = vec2(0.0);
        state.sector_areas[j] = 0.0;
    }
    state.inner_ellipse_0 = vec2(1.0, 0.0);
    state.sector_total = 0.0;
    state.proxy_sector_areas = false;
    state.projected_solid_angle = 0.0;
    return state;
}

SolidAngleSampler solid_angle_sampler_empty() {
    SolidAngleSampler state;
    state.count = 0;
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        state.directions[j] = vec3(0.0);
    }
    for (int j = 0; j < MAX_FAN_TRIANGLES; ++j) {
        state.triangles[j] = vec3(0.0);
        state.fan_solid_angles[j] = 0.0;
    }
    state.solid_angle = 0.0;
    state.orientation = 1.0;
    return state;
}
