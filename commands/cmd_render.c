/* `tissuebench render`: pictures of a mesh file, or of a scene at chosen
 * times (or every k steps), headless (render/tb_render.h): the body's
 * surface shaded or coloured by displacement or von Mises stress with a
 * colour bar, the instrument, the ground, a wireframe, the model's
 * structure (measure/tb_draw.h) and the triangles crossing the instrument. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "tb_cli.h"
#include "core/tb_mesh_io.h"
#include "core/tb_parse.h"
#include "measure/tb_draw.h"
#include "measure/tb_fidelity.h"
#include "render/tb_render.h"
#include "scenes/tb_sim.h"

#define PROG "tissuebench render"

typedef struct opts {
  const char *view, *camera, *color, *out, *scene;
  int w, h, ss, wireframe, structure, contacts, volume;
  tb_vec3 up; /* the view's up direction: --up, else the scene's (against gravity), else z */
  int up_given;
  double range[2]; /* the colour map's range: --range, else 0 to the frames' robust top */
  int range_given;
} opts;

static int bad(const char *fmt, const char *a) {
  fprintf(stderr, PROG ": ");
  fprintf(stderr, fmt, a);
  fputc('\n', stderr);
  return TB_EXIT_INPUT;
}

static const float BG[3] = {1, 1, 1};

/* --camera, or the view (default left-front) fitted to the points x (the body at rest). */
static int camera_for(const opts *o, const tb_vec3 *x, int n, tb_camera *cam, tb_error *err) {
  if (o->camera) return tb_camera_parse(o->camera, cam, err);
  if (tb_camera_preset_points(o->view ? o->view : "left-front", x, n, o->up, (double)o->w / o->h,
                              cam))
    return tb_error_set(err, "--view", 0, "unknown view '%s' (front, left-front, left-back, top)",
                        o->view);
  return 0;
}

/* Von Mises stress per node: the mean over its tets (scenes/output.c's
 * per-tet stress). */
static int vertex_stress(const tb_sim *s, double *out) {
  int nt = s->mesh.ntet, nv = s->mesh.nv;
  double *vm = malloc(sizeof(double) * (size_t)(nt > 0 ? nt : 1));
  int *count = calloc((size_t)nv, sizeof(int));
  if (!vm || !count) return free(vm), free(count), -1;
  tb_sim_tet_fields(s, NULL, vm, NULL);
  for (int t = 0; t < nt; t++)
    for (int c = 0; c < 4; c++) {
      int i = s->mesh.tet[4 * t + c];
      if (isfinite(vm[t])) out[i] += vm[t], count[i]++;
    }
  for (int i = 0; i < nv; i++) out[i] = count[i] ? out[i] / count[i] : 0;
  free(vm), free(count);
  return 0;
}

/* Error against the reference solution (measure/tb_fidelity.h): the static
 * problem of the scene's loads at the current time, compressible
 * Neo-Hookean on quadratic tets at the fidelity suites' reference
 * resolution; per surface node |u - u_ref| / max |u_ref| (meaningful once
 * the model has settled). Scenes with a static problem: beam,
 * liver-stretch. */
static int vertex_error(tb_sim *s, const char *scene, double *out, tb_error *err) {
  tb_fid_plan plan;
  if (tb_fid_plan_for(scene, 1, s->def.seed, &plan, err)) return -1;
  tb_sim_def rd = s->def;
  rd.nodes = plan.ref_res;
  tb_fid_ref ref;
  tb_fid_mesh fm;
  if (tb_fid_reference(scene, &rd, s->t, NULL, &ref, err)) return -1;
  int rc = tb_fid_mesh_make(&ref, &s->def, &fm, err);
  if (!rc && (fm.mesh.nv != s->mesh.nv || !(ref.umax > 0)))
    rc = tb_error_set(err, scene, 0, "%s",
                      ref.umax > 0 ? "the reference's sampling mesh is not the scene's"
                                   : "no load at this time: nothing to compare");
  const tb_vec3 *x = tb_model_positions(&s->model);
  for (int q = 0; !rc && q < fm.nsurf; q++) {
    int i = fm.surf[q];
    out[i] = tb_dist(tb_sub(x[i], s->mesh.x[i]), fm.uref[q]) / ref.umax;
  }
  if (!rc) tb_fid_mesh_free(&fm);
  tb_fid_ref_free(&ref);
  return rc;
}

/* The colour map's values at the surface's points (NULL for --color none); *n gets their
 * count. */
static double *surface_values(tb_sim *s, const opts *o, int *n, tb_error *err) {
  tb_surface su = tb_model_surface(&s->model);
  *n = su.nv;
  if (!strcmp(o->color, "none")) return NULL;
  double *value = calloc((size_t)(su.nv > 0 ? su.nv : 1), sizeof(double));
  if (!value || (!strcmp(o->color, "von_mises") && vertex_stress(s, value)))
    return free(value), tb_error_set(err, o->out, 0, "out of memory"), NULL;
  if (!strcmp(o->color, "error") && vertex_error(s, o->scene, value, err)) return free(value), NULL;
  if (!strcmp(o->color, "displacement")) tb_draw_displacement(s, value);
  return value;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The largest value at least 3 values (and 0.1% of them) reach: a spike of one or two points does
 * not set the range, a peak such as a press's dent does. */
static double robust_top(const double *v, int n) {
  double *c = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  if (!c || n < 1) return free(c), 0;
  memcpy(c, v, sizeof(double) * (size_t)n);
  qsort(c, (size_t)n, sizeof(double), cmp_double);
  int k = (int)ceil(0.001 * n);
  double top = c[n - (k > 3 ? k : n < 3 ? n : 3)];
  free(c);
  return top;
}

/* The colour bar's label: the quantity and its unit. */
static const char *color_label(const char *color) {
  return !strcmp(color, "displacement") ? "displacement (mesh length unit)"
         : !strcmp(color, "von_mises")  ? "von Mises stress (unit of E)"
                                        : "error / max |u_ref|";
}

/* One picture of a scene's current state, the colour map over o->range. */
static int frame(tb_renderer *r, tb_sim *s, const opts *o, const tb_camera *cam, const char *path,
                 tb_error *err) {
  tb_renderer_begin(r, cam, BG);
  int n;
  double *value = surface_values(s, o, &n, err);
  if (!value && strcmp(o->color, "none")) return -1;
  if (!o->volume)
    tb_draw_sim(r, s, value, o->range[0], o->range[1], color_label(o->color), o->wireframe);
  if ((o->structure || o->volume) && tb_draw_structure(r, s, err)) return free(value), -1;
  if (o->contacts) tb_draw_contacts(r, s);
  double most = 0;
  for (int i = 0; value && i < n; i++) most = fmax(most, value[i]);
  free(value);
  static const float ink[3] = {0.1f, 0.1f, 0.1f};
  char label[160];
  snprintf(label, sizeof label, "t = %.3f s", s->t);
  tb_renderer_text(r, 0.02, 0.95, 0.035, -1, ink, label);
  snprintf(label, sizeof label, "%s, %s", s->name, s->model.cls->name);
  tb_renderer_text(r, 0.02, 0.91, 0.028, -1, ink, label);
  if (tb_renderer_write_png(r, path, err)) return -1;
  if (strcmp(o->color, "none"))
    printf("%s (%s: largest %.6g, colour range %.6g to %.6g)\n", path, o->color, most, o->range[0],
           o->range[1]);
  else
    printf("%s\n", path);
  return 0;
}

/* "0,0.5,1.5": ascending times >= 0. */
static int parse_times(const char *s, double *t, int cap, int *n) {
  *n = 0;
  while (*s) {
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || errno || !isfinite(v) || v < 0 || *n == cap || (*n && !(v > t[*n - 1])))
      return -1;
    t[(*n)++] = v;
    if (*end == ',')
      end++;
    else if (*end)
      return -1;
    s = end;
  }
  return *n ? 0 : -1;
}

static int render_mesh(const char *file, const opts *o) {
  tb_mesh m;
  tb_error err;
  if (tb_mesh_read(file, &m, &err)) return bad("%s", err.msg);
  if (m.ntri < 1 && m.ntet > 0) m.ntri = tb_mesh_tet_boundary(&m, &m.tri);
  tb_camera cam;
  tb_renderer *r = NULL;
  int rc = TB_EXIT_INPUT;
  if (camera_for(o, m.x, m.nv, &cam, &err) || !(r = tb_renderer_new(o->w, o->h, o->ss, &err))) {
    fprintf(stderr, PROG ": %s\n", err.msg);
  } else {
    tb_renderer_begin(r, &cam, BG);
    tb_render_mesh rm = {.nv = m.nv,
                         .ntri = m.ntri,
                         .x = m.x,
                         .tri = m.tri,
                         .rgb = {tb_draw_body_rgb[0], tb_draw_body_rgb[1], tb_draw_body_rgb[2]},
                         .wireframe = o->wireframe};
    tb_renderer_mesh(r, &rm);
    if (o->structure && m.ntet) tb_draw_edges(r, &m, m.x);
    rc = tb_renderer_write_png(r, o->out, &err) ? TB_EXIT_FAIL : TB_EXIT_OK;
    if (rc)
      fprintf(stderr, PROG ": %s\n", err.msg);
    else
      printf("%s\n", o->out);
  }
  tb_renderer_free(r);
  tb_mesh_free(&m);
  return rc;
}

/* A scene's pictures: the run's settings and, for the first run, the colour range found. */
typedef struct walk {
  opts *o;
  const tb_sim_def *sd;
  const tb_settings *set;
  const char *scene, *model;
  const double *t;
  int nt;
  long every;
  tb_renderer *r;
  const tb_camera *cam;
  double top, floor; /* the frames' largest robust top; the smallest range shown */
} walk;

/* Runs the scene and, at each picture's step, draws it (draw 1) or only measures its colour
 * values into w->top (draw 0). */
static int run(walk *w, int draw) {
  opts *o = w->o;
  tb_sim s;
  tb_error err;
  if (tb_sim_create(&s, w->scene, w->sd, w->model, w->set, NULL, &err)) return bad("%s", err.msg);
  if (!strcmp(o->color, "von_mises") && !tb_sim_tet_fields(&s, NULL, NULL, NULL)) {
    tb_sim_destroy(&s);
    return bad("--color von_mises: model '%s' has no stress (no E and nu: use fem or fem-corot)",
               w->model ? w->model : "of the scene");
  }
  /* round-off is not a deformation: the range is at least 1e-9 of the body's size (of E) */
  double E = 1;
  tb_model_setting(s.model.cls->name, &s.settings, "E", &E);
  w->floor = !strcmp(o->color, "displacement") ? 1e-9 * s.size
             : !strcmp(o->color, "von_mises")  ? 1e-9 * E
                                               : 1e-9;
  if (!o->up_given) o->up = tb_scale(s.desc.gravity_dir, -1);
  double t[256];
  int nt = w->nt;
  memcpy(t, w->t, sizeof(double) * (size_t)nt);
  if (!nt) t[0] = s.def.duration, nt = 1;
  long steps = w->every ? lround(s.def.duration / s.def.dt) : lround(t[nt - 1] / s.def.dt);
  tb_camera cam;
  tb_renderer *r = NULL;
  if (draw && (camera_for(o, s.mesh.x, s.mesh.nv, &cam, &err) ||
               !(r = tb_renderer_new(o->w, o->h, o->ss, &err)))) {
    tb_sim_destroy(&s);
    return bad("%s", err.msg);
  }
  int rc = TB_EXIT_OK, next = 0, count = 0;
  char path[1200];
  for (long k = 0; k <= steps && rc == TB_EXIT_OK; k++) {
    int shoot =
        w->every ? k % w->every == 0 : (next < nt && fabs(k * s.def.dt - t[next]) < 0.5 * s.def.dt);
    if (shoot && !draw) {
      int n;
      double *value = surface_values(&s, o, &n, &err);
      if (!value) {
        fprintf(stderr, PROG ": %s\n", err.msg);
        rc = TB_EXIT_FAIL;
      }
      w->top = fmax(w->top, robust_top(value, n));
      free(value);
      next++;
    } else if (shoot) {
      if (w->every)
        snprintf(path, sizeof path, "%s/frame_%05d.png", o->out, count);
      else
        snprintf(path, sizeof path, "%s/t%.3f.png", o->out, t[next++]);
      if (frame(r, &s, o, &cam, path, &err)) {
        fprintf(stderr, PROG ": %s\n", err.msg);
        rc = TB_EXIT_FAIL;
      } else
        count++;
    }
    if (k < steps && rc == TB_EXIT_OK && tb_sim_step(&s, &err)) {
      printf("status: unstable (%s)\n", err.msg);
      rc = TB_EXIT_FAIL;
    }
  }
  tb_renderer_free(r);
  tb_sim_destroy(&s);
  return rc;
}

int tb_cmd_render(int argc, char **argv) {
  opts o = {NULL, NULL, "none", NULL, NULL, 800, 600, 2, 0, 0, 0, 0, {0, 0, 1}, 0, {0, 0}, 0};
  const char *scene = NULL, *mesh = NULL, *model = NULL, *times = NULL, *size = NULL, *up = NULL,
             *range = NULL;
  long every = 0;
  int ss_given = 0;
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  tb_settings set;
  tb_settings_init(&set);
  tb_error err;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
    if (!strcmp(a, "--wireframe") || !strcmp(a, "--structure") || !strcmp(a, "--contacts") ||
        !strcmp(a, "--volume")) {
      *(a[2] == 'w'   ? &o.wireframe
        : a[2] == 's' ? &o.structure
        : a[2] == 'v' ? &o.volume
                      : &o.contacts) = 1;
      continue;
    }
    if (!v) return tb_cli_bad_option("render", a);
    i++;
    const char **slot = !strcmp(a, "--scene")    ? &scene
                        : !strcmp(a, "--mesh")   ? &mesh
                        : !strcmp(a, "--model")  ? &model
                        : !strcmp(a, "--times")  ? &times
                        : !strcmp(a, "--view")   ? &o.view
                        : !strcmp(a, "--camera") ? &o.camera
                        : !strcmp(a, "--color")  ? &o.color
                        : !strcmp(a, "--out")    ? &o.out
                        : !strcmp(a, "--size")   ? &size
                        : !strcmp(a, "--up")     ? &up
                        : !strcmp(a, "--range")  ? &range
                                                 : NULL;
    if (slot) {
      if (*slot && slot != &o.color) return bad("%s given twice", a);
      *slot = v;
    } else if (!strcmp(a, "--every") || !strcmp(a, "--ss")) {
      char *end;
      long n = strtol(v, &end, 10);
      if (*end || end == v || n < 1 || n > (a[2] == 'e' ? 100000000 : 4))
        return bad("%s needs a whole number (--every >= 1, --ss 1..4)", a);
      if (a[2] == 'e')
        every = n;
      else
        o.ss = (int)n, ss_given = 1;
    } else if (!strcmp(a, "--set")) {
      int rc = tb_sim_def_set(&sd, v, &err);
      if (rc == 1) rc = tb_settings_set(&set, v, &err);
      if (rc) return bad("%s", err.msg);
    } else
      return tb_cli_bad_option("render", a);
  }
  (void)ss_given;
  if (!o.out) return bad("%s", "--out is required (a .png for --mesh, a folder for --scene)");
  if (!scene == !mesh) return bad("%s", "give --scene NAME|FILE or --mesh FILE");
  if (size &&
      (sscanf(size, "%dx%d", &o.w, &o.h) != 2 || o.w < 8 || o.h < 8 || o.w > 8192 || o.h > 8192))
    return bad("--size '%s': expected WxH, each 8..8192", size);
  if (o.view && o.camera) return bad("%s", "give --view or --camera, not both");
  const char *rest;
  if (up &&
      (tb_parse_vec3(up, &o.up, &rest) || *rest || !(tb_len(o.up) > 0) || !isfinite(tb_len(o.up))))
    return bad("--up '%s': a direction x,y,z, not zero", up);
  o.up_given = up != NULL;
  if (range) {
    char *end, *end2;
    o.range[0] = strtod(range, &end);
    o.range[1] = *end == ',' ? strtod(end + 1, &end2) : NAN;
    if (end == range || *end != ',' || end2 == end + 1 || *end2 || !isfinite(o.range[0]) ||
        !isfinite(o.range[1]) || !(o.range[1] > o.range[0]))
      return bad("--range '%s': LO,HI with LO < HI (finite)", range);
  }
  o.range_given = range != NULL;
  if (strcmp(o.color, "none") && strcmp(o.color, "displacement") && strcmp(o.color, "von_mises") &&
      strcmp(o.color, "error"))
    return bad("--color '%s': none, displacement, von_mises or error", o.color);
  if (!strcmp(o.color, "error") &&
      (!scene || (strcmp(scene, "beam") && strcmp(scene, "liver-stretch"))))
    return bad("%s",
               "--color error: the reference solution exists for the scenes beam and "
               "liver-stretch");
  o.scene = scene;
  if (mesh) return render_mesh(mesh, &o);
  double t[256];
  int nt = 0;
  if (times && parse_times(times, t, 256, &nt))
    return bad("--times '%s': ascending times >= 0, comma-separated (at most 256)", times);
  if (times && every) return bad("%s", "give --times or --every, not both");
  if (mkdir(o.out, 0777) && errno != EEXIST) {
    char msg[600];
    snprintf(msg, sizeof msg, "%s: cannot create the folder: %s", o.out, strerror(errno));
    return bad("%s", msg);
  }
  walk w = {&o, &sd, &set, scene, model, t, nt, every, NULL, NULL, 0, 0};
  int rc = TB_EXIT_OK;
  /* the automatic colour range: a first run of the same frames, each frame's robust top
   * (robust_top), the largest of them for every frame (the run is deterministic: the second is
   * the same) */
  if (strcmp(o.color, "none") && !o.range_given) {
    rc = run(&w, 0);
    o.range[1] = w.top > w.floor ? w.top : w.floor;
  }
  if (rc == TB_EXIT_OK) rc = run(&w, 1);
  return rc;
}
