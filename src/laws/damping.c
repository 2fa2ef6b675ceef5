/* The clamped damping law's cold path (law_hooks.h): its refitted beta (H11-H13, H16). */
#include "hertz.h"
#include "law_hooks.h"

/* beta that gives e_eff = e when the normal force cannot pull (laws.c). */
static void derive(adem_pair_params *pp) {
  pp->beta_clamped = adem_damping_beta_clamped(pp->restitution);
}

static double normal_beta(const adem_pair_params *pp) { return pp->beta_clamped; }

const adem_law_hooks adem_damping_clamped_hooks = {.derive = derive, .normal_beta = normal_beta};
