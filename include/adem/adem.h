/* adem: a Discrete Element Method engine for adhesive and granular spheres.
 * Umbrella header: every public header of the library. Each of them also stands alone (a test
 * compiles each by itself), so a program may include only the ones it uses. adem/vec3.h, the
 * inline vector algebra (short names: v3_add, ...), is not in it: include it where it is used. */
#ifndef ADEM_ADEM_H
#define ADEM_ADEM_H

#include "adem/base.h"
#include "adem/laws.h"
#include "adem/world.h"
#include "adem/case.h"
#include "adem/files.h"
#include "adem/run.h"
#include "adem/binding.h"
#include "adem/frames.h"
#include "adem/fields.h"
#include "adem/studies.h"
#include "adem/pile.h"
#include "adem/drum.h"
#include "adem/calibrate.h"

#endif
