/* The per-particle sums of the force pass (force_sums.c). */
#ifndef ADEM_FORCE_SUMS_H
#define ADEM_FORCE_SUMS_H

#include "force_pass.h"

/* Every particle's force, torque, rolling torque and BROF hold from its contacts' results, in
 * an order fixed by ids (and with the balance on, its dissipation and wall work). */
void adem_force_sums(const adem_force_scope *w);

#endif
