/* Reader for adem's particle frames (frames/particles_NNNNNN.vtu): VTK XML UnstructuredGrid with
 * raw appended binary data and UInt64 block headers, as src/output/vtu.c writes them (read by
 * src/output/vtu_read.c). It returns what the pile and ballast studies need: centres, radii, ids
 * and the frame's time.
 *
 * The file is untrusted input: every offset, size and count is checked against the bytes that are
 * there, and a file that is not such a frame is refused with a message that says what is wrong
 * and where (byte offset). The library never prints and never exits. */
#ifndef ADEM_FRAMES_H
#define ADEM_FRAMES_H

#include <stddef.h>
#include <stdint.h>

#include "adem/base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Largest file adem_vtu_read_file accepts (a frame of ten million particles is about 1.9 GB). */
#define ADEM_VTU_READ_MAX_BYTES ((size_t)4 << 30)

/* One particle frame. Arrays of n entries, owned by the frame (adem_vtu_frame_free). */
typedef struct adem_vtu_frame {
  size_t n;
  adem_vec3 *pos;      /* centres, m ("position", the frame's Points) */
  double *radius;      /* m ("radius") */
  int64_t *id;         /* stable particle ids ("id"), or NULL when the file has none */
  adem_vec3 *velocity; /* m/s ("velocity"), or NULL when the file has none */
  double *mass;        /* kg ("mass"), or NULL when the file has none (frames before the array) */
  double time;         /* s, FieldData "TimeValue"; NaN when the file has none */
  int64_t step;        /* FieldData "Step"; -1 when the file has none */
} adem_vtu_frame;

/* Reads a particle frame from memory. NAME is used in messages only (may be NULL). On success
 * *frame holds new arrays; on failure *frame is zeroed (nothing to free), err says why and the
 * status is ADEM_ERR_INPUT (malformed) or ADEM_ERR_NOMEM. Radii must be finite and > 0 and
 * centres finite. */
adem_status adem_vtu_read_memory(const void *data, size_t len, const char *name,
                                 adem_vtu_frame *frame, adem_error *err);

/* Reads a particle frame from a file (at most ADEM_VTU_READ_MAX_BYTES). A file that cannot be
 * opened or read is ADEM_ERR_INPUT, with the system's reason. */
adem_status adem_vtu_read_file(const char *path, adem_vtu_frame *frame, adem_error *err);

void adem_vtu_frame_free(adem_vtu_frame *frame);

/* One contact frame (frames/contacts_NNNNNN.vtp, output.contacts): VTK PolyData of one line per
 * touching contact, from particle a's centre p0 to particle b's centre as a sees it (the
 * minimum image across a periodic face) or to the contact point on a wall, p1. */
typedef struct adem_contact_frame {
  size_t n;
  adem_vec3 *p0, *p1; /* m */
  adem_vec3 *force;   /* force on a, N (on b the opposite) */
  int32_t *kind;      /* 0 particle pair, 1 plane, 2 mesh */
  int64_t *id_a;      /* particle id a */
  int64_t *id_b;      /* particle id b, plane index or mesh group */
  double time;        /* s, NaN when the file has none */
  int64_t step;       /* -1 when the file has none */
} adem_contact_frame;

/* Reads a contact frame, checked as a particle frame is (adem_vtu_read_memory). */
adem_status adem_contact_frame_read_memory(const void *data, size_t len, const char *name,
                                           adem_contact_frame *frame, adem_error *err);
adem_status adem_contact_frame_read_file(const char *path, adem_contact_frame *frame,
                                         adem_error *err);
void adem_contact_frame_free(adem_contact_frame *frame);

/* The world's contacts of its last force pass as a contact frame: the same lines, forces and
 * order as the frame output.contacts would write now (time and step the world's). Free with
 * adem_contact_frame_free. */
typedef struct adem_world adem_world;
adem_status adem_world_contact_frame(const adem_world *w, adem_contact_frame *frame,
                                     adem_error *err);

#ifdef __cplusplus
}
#endif

#endif
