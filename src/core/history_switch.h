/* Contact histories when a material pair's tangential or rolling law changes under live contacts
 * (a stage's `interactions`): each history is read in its law's units (tangential: a force in N
 * or a displacement in m; rolling: a torque in N m or a displacement in m), so it is converted
 * where the conversion is exact and cleared otherwise, its spring energy then dissipated. */
#ifndef ADEM_HISTORY_SWITCH_H
#define ADEM_HISTORY_SWITCH_H

#include "materials.h"
#include "pairs.h"
#include "particles.h"
#include "walls.h"

/* Converts or clears h for a change from the laws (tangential_old, rolling_old) to
 * (tangential_new, rolling_new) (ids of adem/laws.h); returns the spring energy that went, J,
 * and sets *cleared when a part was cleared. */
double adem_history_switch(adem_contact_history *h, int tangential_old, int tangential_new,
                           int rolling_old, int rolling_new, bool *cleared);

/* The tangential and rolling laws of each material pair, 2 per pair (a nm + b; -1 before the
 * table is derived), for adem_history_switch_all once it has changed; NULL when out of memory. */
int *adem_history_laws(const adem_materials *mt);

/* Every touching contact of the lists (particle pairs, planes, mesh slots) through
 * adem_history_switch from the laws `old` gave its materials to those mt gives them now; with
 * balance, the energy that went is added to the particles' dissipated energy (half to each of a
 * pair). Returns the number of contacts whose history was cleared. */
size_t adem_history_switch_all(const adem_materials *mt, const int *old, adem_particles *p,
                               adem_pair_list *pp, adem_pair_list *pw, adem_mesh_pairs *pm,
                               const adem_walls *walls, bool balance);

#endif
