/* Cameras for the renderer: the thesis's views of a body (front,
 * left-front, left-back, top; z up, fitted to the body's box) and cameras
 * given explicitly as text. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_render.h"
#include "core/tb_parse.h"

int tb_camera_preset(const char *name, tb_vec3 lo, tb_vec3 hi, tb_camera *out) {
  static const struct {
    const char *name;
    double azimuth,
        elevation; /* degrees: azimuth from -y toward -x, elevation above the xy plane */
  } views[] = {{"front", 0, 10}, {"left-front", 45, 25}, {"left-back", 135, 25}, {"top", 0, 89.9}};
  for (size_t k = 0; k < sizeof views / sizeof views[0]; k++) {
    if (strcmp(views[k].name, name)) continue;
    double a = views[k].azimuth * M_PI / 180, e = views[k].elevation * M_PI / 180;
    tb_vec3 c = tb_scale(tb_add(lo, hi), 0.5);
    double radius = 0.5 * tb_dist(lo, hi), fov = 30;
    double dist = radius / sin(0.5 * fov * M_PI / 180) * 1.05;
    tb_vec3 dir = tb_v3(-sin(a) * cos(e), -cos(a) * cos(e), sin(e));
    out->eye = tb_madd(c, dist, dir), out->target = c;
    out->up = views[k].elevation > 89 ? tb_v3(0, 1, 0) : tb_v3(0, 0, 1);
    out->fov_deg = fov, out->half_height = 0;
    return 0;
  }
  return -1;
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
