// The guard (gc, gmul), the bounds of one factor (Jet) and their rules (chain, product, jet_max),
// unit vector fields and the jets of their cosines (Field, Curvature, Angles, cosine).
// Twin: `src/shading/estimator/jet.rs`; proven equal with the rest of the estimator by
// `tests/multirate.rs` (`control_stage_levels_equal_the_twin`).
// A part of estimator.glsl, which includes the parts in dependency order: include that
// header, not this file.

// Saturates bounds at BIG and remembers that it did (`Guard` in Rust), passed to every function
// that may saturate as Rust passes `&Guard`. `bad`: a bound overflowed (or was NaN), and the
// estimate falls back (Singular). `term`: the term whose share of the second derivative the jets
// carry in this pass, or T_ALL (Rust carries every term at once, see Jet); add_light sets it.
struct Guard {
    bool bad;
    int term;
};

const Guard FRESH_GUARD = Guard(false, T_ALL);

P float gc(float x, inout Guard gd) {
    if (x <= BIG) {
        return x;
    }
    gd.bad = true;
    return BIG;
}
P float gmul(float a, float b, inout Guard gd) {
    P float p = a * b;
    return gc(p, gd);
}

// The bounds of one factor (see `Jet` in Rust): m >= sup|f|, g >= sup|Df|, and h, the part of
// sup|D^2 f| booked under the guard's term, or all of it (`Jet::t`) when that is T_ALL. Rust
// carries all 13 terms and their sum at once; every operation on them acts on each separately
// (scaling, sums, the guard), so a pass here gets the same value as Rust for its term. The levels
// are decided on the sum: one pass per level (`add_light`); the Uniform split adds one pass per
// term.
struct Jet {
    float m;
    float g;
    float h;
};

// Whether this pass carries the parts booked under `term`.
bool booked(int term, Guard gd) {
    return gd.term == term || gd.term == T_ALL;
}

Jet jet_constant(float m) {
    return Jet(m, 0.0, 0.0);
}

Jet guard_jet(Jet j, inout Guard gd) {
    return Jet(gc(j.m, gd), gc(j.g, gd), gc(j.h, gd));
}

// Chain rule for phi(c), with the jet `inner` of c, |phi| <= value, |phi'| <= first and
// |phi''| <= second; phi's own curvature is booked under `term` (`chain` in Rust).
Jet chain(Jet inner, float value, float first, float second, int term, inout Guard gd) {
    Jet j = jet_constant(0.0);
    j.h = gmul(inner.h, first, gd);
    P float inner2 = gmul(inner.g, inner.g, gd);
    P float curvature = gmul(second, inner2, gd);
    if (booked(term, gd)) {
        j.h = gc(j.h + curvature, gd);
    }
    j.m = value;
    j.g = gmul(first, inner.g, gd);
    return guard_jet(j, gd);
}

// Product rule for k (2 or 5) factors, as `product` in Rust (the cross terms go to T_CROSS,
// in the same order).
Jet product(Jet f[5], int k, inout Guard gd) {
    P float m = 1.0;
    for (int j = 0; j < k; ++j) {
        m = gmul(m, f[j].m, gd);
    }
    Jet o = jet_constant(m);
    for (int i = 0; i < k; ++i) {
        P float others = 1.0;
        for (int j = 0; j < k; ++j) {
            if (j != i) {
                others = gmul(others, f[j].m, gd);
            }
        }
        P float gi = gmul(f[i].g, others, gd);
        o.g = gc(o.g + gi, gd);
        P float hi = gmul(f[i].h, others, gd);
        o.h = gc(o.h + hi, gd);
        for (int j = i + 1; j < k; ++j) {
            P float rest = 2.0;
            for (int l = 0; l < k; ++l) {
                if (l != i && l != j) {
                    rest = gmul(rest, f[l].m, gd);
                }
            }
            P float gg = gmul(f[i].g, f[j].g, gd);
            P float cr = gmul(gg, rest, gd);
            if (booked(T_CROSS, gd)) {
                o.h = gc(o.h + cr, gd);
            }
        }
    }
    return o;
}

Jet product2(Jet a, Jet b, inout Guard gd) {
    Jet f[5] = Jet[5](a, b, a, a, a);
    return product(f, 2, gd);
}

// A unit vector field u = m/|m|: w >= |Dm|/|m|, radial >= |u.Dm|/|m|, x >= |P m''|/|m|, and

// the term its curvature is booked under.
struct Field {
    float w;
    float radial;
    float x;
    int term;
};

// max sin(psi) over [p0, p1] in [0, pi].
P float max_sin(float p0, float p1) {
    if (p0 <= HALF_PI && p1 >= HALF_PI) {
        return 1.0;
    }
    P float s = rmax(rmax(est_sin(p0), est_sin(p1)), 0.0);
    return s;
}

// max phi(psi) over [p0, p1], phi = c/2 + sqrt(1 - 3c^2/4), c = |cos psi| (c0, c1 at the ends).
P float max_phi(float p0, float p1, float c0, float c1) {
    P float lo;
    P float hi;
    if (p0 <= HALF_PI && p1 >= HALF_PI) {
        lo = 0.0;
        hi = rmax(c0, c1);
    } else {
        lo = rmin(c0, c1);
        hi = rmax(c0, c1);
    }
    P float c = clamp(INV_SQRT3, lo, hi);
    P float r = rmin(0.5 * c + sqrt(rmax(1.0 - 0.75 * c * c, 0.0)), K23);
    return r;
}

// max cos^p(psi) sin^q(psi) over [a, b] in [0, pi/2].
P float max_cos_sin(float p, float q, float a, float b) {
    P float peak = p > 0.0 ? est_atan2(sqrt(q / p), 1.0) : HALF_PI;
    P float x = clamp(peak, a, b);
    P float c = rmax(est_cos(x), 0.0);
    P float s = rmax(est_sin(x), 0.0);
    P float cp = p == 0.0 ? 1.0 : est_pow(c, p);
    P float sq = q == 0.0 ? 1.0 : est_pow(s, q);
    P float r = cp * sq;
    return r;
}

// The second derivative of a cosine a.b split by sign (see `Curvature` in Rust): turn >=
// |Da|^2 + |Db|^2 (the part -t(|Da|^2 + |Db|^2) <= 0 where t >= 0), rest >= the others.
struct Curvature {
    float turn;
    float rest;
};

Curvature curvature(Field a, Field b, vec2 psi, inout Guard gd) {
    P float s_max = max_sin(psi.x, psi.y);
    P float across_a = gc(2.0 * gmul(a.w, a.radial, gd) + a.x, gd);
    P float across_b = gc(2.0 * gmul(b.w, b.radial, gd) + b.x, gd);
    P float turn = gc(gmul(a.w, a.w, gd) + gmul(b.w, b.w, gd), gd);
    P float rest = gc(2.0 * a.w * b.w + s_max * gc(across_a + across_b, gd), gd);
    return Curvature(turn, rest);
}

// What the jets need of an angle range between two unit fields (see `Angles` in Rust).
struct Angles {
    float s_max;
    float c_max;
    float phi;
};

// The same with the cosines of the range's ends given (see `Angles::with_cosines`).
Angles angles_with(vec2 psi, vec2 cosines) {
    P float c0 = abs(cosines.x);
    P float c1 = abs(cosines.y);
    return Angles(max_sin(psi.x, psi.y), rmax(c0, c1), max_phi(psi.x, psi.y, c0, c1));
}

Angles angles_of(vec2 psi) {
    return angles_with(psi, vec2(est_cos(psi.x), est_cos(psi.y)));
}

// >= |D^2 u . b| for the field f and a unit b at an angle in the range (`Angles::seen`).
P float seen(Angles an, Field f, inout Guard gd) {
    P float w2 = gmul(f.w, f.w, gd);
    P float turning = gmul(an.phi, w2, gd);
    P float radial = gc(an.c_max * w2 + 2.0 * an.s_max * gmul(f.w, f.radial, gd), gd);
    P float r = gc(rmin(turning, radial) + an.s_max * f.x, gd);
    return r;
}

// Jet of c = a.b where the angle between them has the Angles `an` (neither a nor b books under
// T_DOT; they may share a term, as a polygon's emitter cosine does).
Jet cosine_at(Field a, Field b, Angles an, inout Guard gd) {
    P float s_max = an.s_max;
    Jet j = jet_constant(an.c_max);
    P float ha = seen(an, a, gd);
    P float hb = seen(an, b, gd);
    P float hd = gc(2.0 * a.w * b.w, gd);
    if (booked(a.term, gd)) {
        j.h = ha;
    }
    if (booked(b.term, gd)) {
        j.h = j.h + hb;
    }
    if (booked(T_DOT, gd)) {
        j.h = j.h + hd;
    }
    j.g = gc(s_max * (a.w + b.w), gd);
    return j;
}

// The same for the angle range psi.
Jet cosine(Field a, Field b, vec2 psi, inout Guard gd) {
    return cosine_at(a, b, angles_of(psi), gd);
}

// Elementwise larger bounds of two jets (see `jet_max`).
Jet jet_max(Jet a, Jet b) {
    return Jet(rmax(a.m, b.m), rmax(a.g, b.g), rmax(a.h, b.h));
}
