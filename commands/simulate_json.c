/* `simulate --json FILE`: the run's summary for programs, one JSON object (RFC 8259). Times in
 * milliseconds and seconds, lengths in the mesh's unit, as the keys say; numbers that are not
 * finite are null. */
#include <math.h>
#include <stdio.h>

#include "tb_cli.h"
#include "core/tb_threads.h"

static void str(FILE *f, const char *s) {
  fputc('"', f);
  for (; s && *s; s++) {
    unsigned char c = (unsigned char)*s;
    if (c == '"' || c == '\\')
      fprintf(f, "\\%c", c);
    else if (c < 0x20)
      fprintf(f, "\\u%04x", c);
    else
      fputc(c, f);
  }
  fputc('"', f);
}

static void num(FILE *f, const char *key, double v, int comma) {
  fprintf(f, "  \"%s\": ", key);
  if (isfinite(v))
    fprintf(f, "%.17g", v);
  else
    fputs("null", f);
  fputs(comma ? ",\n" : "\n", f);
}

int tb_simulate_json(const char *path, const tb_sim *s, const tb_run_summary *r, tb_error *err) {
  FILE *f = fopen(path, "w");
  if (!f) return tb_error_set(err, path, 0, "cannot write the file");
  fputs("{\n  \"scene\": ", f);
  str(f, s->name);
  fputs(",\n  \"model\": ", f);
  str(f, s->model.cls->name);
  fputs(",\n  \"status\": ", f);
  str(f, r->status);
  fputs(",\n  \"reason\": ", f);
  str(f, r->reason);
  fputs(",\n", f);
  num(f, "nodes", s->mesh.nv, 1);
  num(f, "tets", s->mesh.ntet, 1);
  num(f, "surface_vertices_meshed_by_tetgen", s->meshed_nv ? s->meshed_nv : NAN, 1);
  num(f, "dt_s", s->def.dt, 1);
  num(f, "steps", (double)r->steps, 1);
  num(f, "t_end_s", s->t, 1);
  num(f, "threads", tb_threads(), 1);
  num(f, "time_per_step_cpu_median_ms", r->cpu_ms, 1);
  num(f, "time_per_step_wall_median_ms", r->wall_ms, 1);
  num(f, "time_per_step_cpu_min_ms", r->cpu_min_ms, 1);
  num(f, "time_per_step_cpu_max_ms", r->cpu_max_ms, 1);
  const tb_sim_metrics *m = &r->m;
  int have = r->have_metrics;
  num(f, "max_displacement", have ? m->max_disp : NAN, 1);
  num(f, "max_displacement_node", have ? m->max_disp_node : NAN, 1);
  num(f, "rms_displacement", have ? m->rms_disp : NAN, 1);
  num(f, "volume_change_fraction", have ? m->volume_change : NAN, 1);
  num(f, "inverted_tets", have ? m->inverted : NAN, 1);
  num(f, "energy", have ? m->energy : NAN, 1);
  num(f, "max_node_speed_per_s", have ? r->speed : NAN, 1);
  num(f, "rest_speed_per_s", have ? r->rest_tol : NAN, 1);
  fprintf(f, "  \"at_rest\": %s,\n", have && r->rest ? "true" : "false");
  num(f, "probe_nodes", s->nprobe, 1);
  num(f, "probe_peak_mean_displacement", s->nprobe ? s->probe_peak : NAN, 1);
  num(f, "probe_peak_t_s", s->nprobe ? s->probe_peak_t : NAN, 1);
  num(f, "ground_penetration_max", s->has_ground ? s->pen_ground_max : NAN, 1);
  num(f, "instrument_penetration_max", s->has_tool ? s->pen_tool_max : NAN, 0);
  fputs("}\n", f);
  int bad = ferror(f);
  if (fclose(f) || bad) return tb_error_set(err, path, 0, "write failed");
  return 0;
}
