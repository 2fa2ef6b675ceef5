/* What a run writes: VTU particle frames with a PVD collection, a CSV time series and an
 * energy plot. Every file goes through fileio (atomic) except the CSV, which is appended one
 * whole row per write so that a crash never leaves half a row. */
#ifndef ADEM_OUTPUT_H
#define ADEM_OUTPUT_H

#include <stdbool.h>
#include "adem/world.h"
#include "mesh.h"

/* The mesh as a VTU UnstructuredGrid of triangles with cell data group, normal, force (the force
 * the particles exert on each face, 3 doubles per face; NULL writes zeros) and pressure
 * (|force| / area). Atomic (fileio), raw appended binary like the particle frames. */
adem_status adem_mesh_write_vtu(const adem_mesh *mesh, const double *face_force, const char *path,
                                adem_error *err);

/* One VTU file: UnstructuredGrid of vertex cells, raw appended binary data with UInt64 block
 * headers; point data radius, id, material, velocity, angular_velocity, force, rolling_torque
 * (the rolling resistance torque of the last force pass), mass. */
adem_status adem_output_write_vtu(const adem_world *w, const char *path, adem_error *err);
/* The same of the n particles at idx (in that order); idx NULL: every particle. */
adem_status adem_output_write_vtu_of(const adem_world *w, const uint32_t *idx, size_t n,
                                     const char *path, adem_error *err);
/* A ParaView .pvtu: the point arrays of a particle frame and its pieces (.vtu files, paths
 * relative to the .pvtu's folder). */
adem_status adem_output_write_pvtu(const char *path, const char *const *pieces, int npieces,
                                   adem_error *err);

/* The PVD collection: one (time, file) entry per frame, rewritten after each frame. */
typedef struct adem_pvd {
  size_t n, cap;
  double *time;
  char **file; /* relative to the PVD's folder */
} adem_pvd;
adem_status adem_output_pvd_add(adem_pvd *pvd, double time, const char *file, adem_error *err);
adem_status adem_output_pvd_write(const adem_pvd *pvd, const char *path, adem_error *err);
void adem_output_pvd_free(adem_pvd *pvd);

/* Particles that get their own CSV columns (output.track): for each, p<id>_rolling_torque_x_Nm,
 * _y_, _z_ (rolling resistance torque), p<id>_omega_x_rad_s, _y_, _z_ (angular velocity) and
 * p<id>_distance_m, the path length its centre has travelled (sum of |v| dt). */
typedef struct adem_output_track {
  int n;
  const uint64_t *id; /* stable ids */
} adem_output_track;

/* Columns the caller computes (the run's output.regions), after all others: their names, and a
 * value of each per row. */
typedef struct adem_output_extra {
  int n;
  const char *const *name;
  const double *value; /* n values of the current row */
} adem_output_extra;

/* The header line of the CSV time series (with the final newline); a fresh string. track and
 * extra may be NULL. */
char *adem_output_csv_header(const adem_world *w, const adem_output_track *track,
                             const adem_output_extra *extra);
/* One CSV row (with the final newline) for the world's current state; a fresh string. */
char *adem_output_csv_row(const adem_world *w, const adem_output_track *track,
                          const adem_output_extra *extra);

/* Energy-vs-time PNG from the CSV, drawn by gnuplot. A missing or failing gnuplot is only
 * a warning (logged): the status is ADEM_OK then; ADEM_ERR_IO only if the PNG cannot be placed. */
adem_status adem_output_plot_energy(const char *csv_path, const char *png_path, const char *title,
                                    adem_error *err);

/* Wall-load PNG (loads.png) from the CSV: each mesh group's and plane's force along gravity
 * against time, with the particles' weight. Like the energy plot, a missing gnuplot is a warning. */
adem_status adem_output_plot_loads(const adem_world *w, const char *csv_path, const char *png_path,
                                   const char *title, adem_error *err);

/* The output of one run: files under dir, the PVD entries and the open CSV. */
typedef struct adem_output {
  char *dir, *pvd_path, *csv_path, *png_path;
  bool frames, csv; /* which outputs are on */
  adem_pvd pvd;
  size_t next_frame;       /* index of the next VTU file */
  int csv_fd;              /* -1 when closed */
  adem_output_track track; /* points into the caller's arrays, which must outlive the output */
  adem_output_extra extra; /* the same */
  /* output.contacts (contact_frames.c): contact frames with every contacts_every-th particle
   * frame (0: none), listed in contacts.pvd; contacts_csv: a CSV of each too */
  int contacts_every;
  bool contacts_csv;
  adem_pvd contacts_pvd;
} adem_output;

/* Creates dir (and dir/frames) and checks they can be written: ADEM_ERR_INPUT with a clear
 * message if not. A fresh run starts new PVD and CSV files. A resumed run (resume = true) keeps
 * the first frames_done PVD entries (missing ones are re-created with time k * frame_period) and
 * truncates the CSV to the rows with time <= t_resume (< t_resume with drop_resume_row: the row
 * of that time was the end of a run that now goes on), then appends. */
adem_status adem_output_open(adem_output *o, const char *dir, const adem_world *w, bool frames,
                             bool csv, bool resume, size_t frames_done, double frame_period,
                             double t_resume, bool drop_resume_row,
                             const adem_output_track *track, const adem_output_extra *extra,
                             adem_error *err);
/* Writes frames/particles_NNNNNN.vtu and rewrites the PVD; with mesh walls also
 * frames/mesh_NNNNNN.vtu (face force and pressure) and mesh.pvd, the same times. */
adem_status adem_output_frame(adem_output *o, const adem_world *w, adem_error *err);
/* A frame in pieces (output.pieces, a run split over processes): each process writes its piece
 * dir/frames/particles_NNNNNN_pK.vtu (index the frame's, K its rank) of the n particles at idx
 * with adem_output_frame_piece; then the writer, with adem_output_frame_pvtu, the frame's
 * frames/particles_NNNNNN.pvtu naming the npieces pieces, the PVD entry and the mesh frame. */
adem_status adem_output_frame_piece(const char *dir, size_t index, int piece, const adem_world *w,
                                    const uint32_t *idx, size_t n, adem_error *err);
adem_status adem_output_frame_pvtu(adem_output *o, const adem_world *w, int npieces,
                                   adem_error *err);
/* Appends one CSV row with a single write (the extra columns' values read from o->extra.value
 * now). */
adem_status adem_output_csv_append(adem_output *o, const adem_world *w, adem_error *err);
void adem_output_close(adem_output *o);

/* Contact frames (output.contacts): after adem_output_open, switches them on with every
 * every-th particle frame (frame index k with k % every == 0), as frames/contacts_NNNNNN.vtp
 * (and .csv with csv) listed in contacts.pvd. A resumed run keeps the entries of contacts.pvd
 * of frames before frames_done and rewrites it. every 0: off. */
adem_status adem_output_contacts_open(adem_output *o, int every, bool csv, bool resume,
                                      size_t frames_done, adem_error *err);
/* The contact frame of particle frame o->next_frame, if due (called by the particle frame). */
adem_status adem_output_contacts_frame(adem_output *o, const adem_world *w, adem_error *err);

#endif
