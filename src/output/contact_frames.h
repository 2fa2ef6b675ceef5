/* Contact frames (output.contacts): the touching contacts of the last force pass as a VTK PolyData
 * file of line cells, frames/contacts_NNNNNN.vtp, listed in contacts.pvd with the particle frames'
 * times, and on request the same as frames/contacts_NNNNNN.csv. Each line runs from particle a's
 * centre to particle b's centre as a sees it (the minimum image across a periodic face) or, for a
 * wall, to the contact point on the wall. Files are written atomically (fileio). */
#ifndef ADEM_CONTACT_FRAMES_H
#define ADEM_CONTACT_FRAMES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "adem/world.h"
#include "world_internal.h"

/* One touching contact as the frames write it. */
typedef struct adem_contact_record {
  int32_t kind;                             /* adem_contact_kind: 0 particle, 1 plane, 2 mesh */
  int64_t a, b;                             /* particle id a (the lower id of a pair); b: particle id, plane index or
                                             * mesh group index */
  adem_vec3 p0, p1;                         /* a's centre; b's centre (minimum image) or the contact point on the wall */
  adem_vec3 force;                          /* force on a, N (on b the opposite) */
  adem_vec3 normal_force, tangential_force; /* its parts along and across n = (p1 - p0)/|p1 - p0| */
  adem_vec3 rolling_torque;                 /* rolling resistance couple on a, N m */
  double overlap;                           /* r_a + r_b - |p1 - p0| (a wall: r_a - |p1 - p0|), m; < 0 for an adhesive
                                             * neck that has not broken yet */
} adem_contact_record;

/* The touching contacts in a fixed order that neither the storage order, the thread count nor
 * the process count changes: particle pairs by (a, b), then plane contacts by (a, plane), then
 * mesh contacts by a and the slot order (by region key). *out is a fresh array (NULL when none). */
adem_status adem_contact_records(const adem_world *w, adem_contact_record **out, size_t *n,
                                 adem_error *err);

/* frames/contacts_NNNNNN.vtp of the world's contacts (time and step as FieldData). */
adem_status adem_contact_write_vtp(const adem_world *w, const adem_contact_record *c, size_t n,
                                   const char *path, adem_error *err);
/* The same as CSV: the header line adem_contact_csv_header, one row per contact. */
adem_status adem_contact_write_csv(const adem_contact_record *c, size_t n, const char *path,
                                   adem_error *err);
extern const char adem_contact_csv_header[];

#endif
