/* Cameras for the renderer: the thesis's views of a body (front,
 * left-front, left-back, top; any up direction, the body's box fitted to
 * the view) and cameras given explicitly as text. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_render.h"
#include "core/tb_parse.h"

int tb_camera_preset_points(const char *name, const tb_vec3 *x, int n, tb_vec3 up, double aspect,
                            tb_camera *out) {
  static const struct {
    const char *name;
    double azimuth, elevation; /* degrees: azimuth from the front toward the left, elevation */
  } views[] = {{"front", 0, 10}, {"left-front", 45, 25}, {"left-back", 135, 25}, {"top", 0, 89.9}};
  if (!(tb_len(up) > 0) || !(aspect > 0) || n < 1) return -1;
  /* right, back and up: x, y, z for z up; for y up, x, -z, y (the front seen from +z) */
  tb_vec3 u = tb_normalize(up), ax = fabs(u.x) < 0.9 ? tb_v3(1, 0, 0) : tb_v3(0, 1, 0);
  tb_vec3 right = tb_normalize(tb_sub(ax, tb_scale(u, tb_dot(ax, u)))), back = tb_cross(u, right);
  for (size_t k = 0; k < sizeof views / sizeof views[0]; k++) {
    if (strcmp(views[k].name, name)) continue;
    double a = views[k].azimuth * M_PI / 180, e = views[k].elevation * M_PI / 180, fov = 30;
    tb_vec3 dir =
        tb_add(tb_add(tb_scale(right, -sin(a) * cos(e)), tb_scale(back, -cos(a) * cos(e))),
               tb_scale(u, sin(e)));
    tb_vec3 cam_up = views[k].elevation > 89 ? back : u;
    tb_vec3 cr = tb_normalize(tb_cross(tb_scale(dir, -1), cam_up));
    tb_vec3 cu = tb_cross(cr, tb_scale(dir, -1));
    /* the target: the middle of the points' extent across the view */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < n; i++) {
      double c[3] = {tb_dot(x[i], cr), tb_dot(x[i], cu), tb_dot(x[i], dir)};
      for (int j = 0; j < 3; j++) lo[j] = fmin(lo[j], c[j]), hi[j] = fmax(hi[j], c[j]);
    }
    tb_vec3 c =
        tb_add(tb_add(tb_scale(cr, 0.5 * (lo[0] + hi[0])), tb_scale(cu, 0.5 * (lo[1] + hi[1]))),
               tb_scale(dir, 0.5 * (lo[2] + hi[2])));
    /* the nearest distance at which every point is inside the view, the points filling 90% of
     * its height or width */
    double t = tan(0.5 * fov * M_PI / 180) * 0.9, dist = 0;
    for (int i = 0; i < n; i++) {
      tb_vec3 d = tb_sub(x[i], c);
      double z = tb_dot(d, dir);
      dist = fmax(dist, z + fabs(tb_dot(d, cu)) / t);
      dist = fmax(dist, z + fabs(tb_dot(d, cr)) / (t * aspect));
    }
    if (!(dist > 0) || !isfinite(dist)) dist = 1;
    out->eye = tb_madd(c, dist, dir), out->target = c, out->up = cam_up;
    out->fov_deg = fov, out->half_height = 0;
    return 0;
  }
  return -1;
}

int tb_camera_preset_up(const char *name, tb_vec3 lo, tb_vec3 hi, tb_vec3 up, double aspect,
                        tb_camera *out) {
  tb_vec3 corner[8];
  for (int q = 0; q < 8; q++)
    corner[q] = tb_v3(q & 1 ? hi.x : lo.x, q & 2 ? hi.y : lo.y, q & 4 ? hi.z : lo.z);
  return tb_camera_preset_points(name, corner, 8, up, aspect, out);
}

int tb_camera_preset(const char *name, tb_vec3 lo, tb_vec3 hi, tb_camera *out) {
  return tb_camera_preset_up(name, lo, hi, tb_v3(0, 0, 1), 4.0 / 3.0, out);
}

int tb_camera_parse(const char *spec, tb_camera *out, tb_error *err) {
  memset(out, 0, sizeof *out);
  out->up = tb_v3(0, 0, 1);
  int have_eye = 0, have_target = 0;
  char buf[512];
  if (strlen(spec) >= sizeof buf) return tb_error_set(err, "--camera", 0, "too long");
  strcpy(buf, spec);
  for (char *tok = strtok(buf, " ;"); tok; tok = strtok(NULL, " ;")) {
    char *eq = strchr(tok, '=');
    if (!eq) return tb_error_set(err, "--camera", 0, "'%s' is not key=value", tok);
    *eq = 0;
    const char *k = tok, *v = eq + 1;
    if (!strcmp(k, "eye") || !strcmp(k, "target") || !strcmp(k, "up")) {
      tb_vec3 *dst = k[0] == 'e' ? &out->eye : k[0] == 't' ? &out->target : &out->up;
      const char *rest;
      if (tb_parse_vec3(v, dst, &rest) || *rest)
        return tb_error_set(err, "--camera", 0, "%s: '%s' is not x,y,z", k, v);
      have_eye |= k[0] == 'e', have_target |= k[0] == 't';
    } else if (!strcmp(k, "fov") || !strcmp(k, "ortho")) {
      char *end;
      errno = 0;
      double x = strtod(v, &end);
      if (end == v || *end || errno || !(x > 0) || !isfinite(x) || (k[0] == 'f' && x >= 170))
        return tb_error_set(err, "--camera", 0, "%s: '%s' must be a number > 0%s", k, v,
                            k[0] == 'f' ? " and < 170 (degrees)" : "");
      if (k[0] == 'f')
        out->fov_deg = x;
      else
        out->half_height = x;
    } else
      return tb_error_set(err, "--camera", 0, "unknown key '%s' (eye, target, up, fov, ortho)", k);
  }
  if (!have_eye || !have_target) return tb_error_set(err, "--camera", 0, "needs eye= and target=");
  if (!(out->fov_deg > 0) && !(out->half_height > 0)) out->fov_deg = 30;
  if (out->fov_deg > 0 && out->half_height > 0)
    return tb_error_set(err, "--camera", 0,
                        "give fov= (perspective) or ortho= (orthographic), not both");
  tb_vec3 f = tb_sub(out->target, out->eye);
  if (!(tb_len(f) > 0)) return tb_error_set(err, "--camera", 0, "eye and target coincide");
  if (!(tb_len(tb_cross(f, out->up)) > 1e-12 * tb_len(f) * tb_len(out->up)))
    return tb_error_set(err, "--camera", 0, "up is parallel to the view direction (or zero)");
  return 0;
}
