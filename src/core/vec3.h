/* vec3.h — tiny inline helpers for xyz triples stored in flat double arrays. */
#ifndef Q2N_CORE_VEC3_H
#define Q2N_CORE_VEC3_H

#include <math.h>

/* π (math.h's M_PI is POSIX, not C11). */
#define Q2N_PI 3.14159265358979323846

static inline void q2n_v3_sub(double r[3], const double a[3], const double b[3])
{ r[0] = a[0] - b[0]; r[1] = a[1] - b[1]; r[2] = a[2] - b[2]; }
static inline void q2n_v3_add(double r[3], const double a[3], const double b[3])
{ r[0] = a[0] + b[0]; r[1] = a[1] + b[1]; r[2] = a[2] + b[2]; }
static inline void q2n_v3_axpy(double r[3], double s, const double a[3])
{ r[0] += s * a[0]; r[1] += s * a[1]; r[2] += s * a[2]; }
static inline void q2n_v3_scale(double r[3], double s, const double a[3])
{ r[0] = s * a[0]; r[1] = s * a[1]; r[2] = s * a[2]; }
static inline double q2n_v3_dot(const double a[3], const double b[3])
{ return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static inline void q2n_v3_cross(double r[3], const double a[3], const double b[3])
{
    double x = a[1] * b[2] - a[2] * b[1], y = a[2] * b[0] - a[0] * b[2], z = a[0] * b[1] - a[1] * b[0];
    r[0] = x; r[1] = y; r[2] = z;
}
static inline double q2n_v3_norm(const double a[3]) { return sqrt(q2n_v3_dot(a, a)); }
/* Angle between a and b in radians, 0..pi (atan2 of |a x b| and a . b: accurate near 0 and pi). */
static inline double q2n_v3_angle(const double a[3], const double b[3])
{
    double c[3];
    q2n_v3_cross(c, a, b);
    return atan2(q2n_v3_norm(c), q2n_v3_dot(a, b));
}
/* Angle in degrees of the corner at p between its edges to q and r. */
static inline double q2n_v3_corner_deg(const double p[3], const double q[3], const double r[3])
{
    double a[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, b[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    return q2n_v3_angle(a, b) * (180.0 / 3.14159265358979323846);
}
/* Sine of the corner at p between its edges to `next` and `prev` (next - p turning towards prev - p),
 * signed by the normal n of length nn: positive where the corner turns n's way.  -2 when an edge has
 * no length. */
static inline double q2n_v3_corner_sine(const double p[3], const double next[3], const double prev[3], const double n[3],
                                        double nn)
{
    double a[3], b[3], c[3];
    q2n_v3_sub(a, next, p);
    q2n_v3_sub(b, prev, p);
    double la = q2n_v3_norm(a), lb = q2n_v3_norm(b);
    if (!(la > 0 && lb > 0)) return -2;
    q2n_v3_cross(c, a, b);
    return q2n_v3_dot(c, n) / (nn * la * lb);
}
static inline double q2n_v3_dist(const double a[3], const double b[3])
{ double d[3]; q2n_v3_sub(d, a, b); return q2n_v3_norm(d); }
/* The same without overflow or underflow in the squares: for vectors whose components may pass
 * 1e154 (a model at 1e200 units, where rounding alone puts points 1e184 apart). */
static inline double q2n_v3_norm_scaled(const double a[3])
{
    double m = fmax(fabs(a[0]), fmax(fabs(a[1]), fabs(a[2])));
    if (!(m > 0) || !isfinite(m)) return m;
    double x = a[0] / m, y = a[1] / m, z = a[2] / m;
    return m * sqrt(x * x + y * y + z * z);
}
static inline double q2n_v3_dist_scaled(const double a[3], const double b[3])
{ double d[3]; q2n_v3_sub(d, a, b); return q2n_v3_norm_scaled(d); }

#endif
