/* Reading whole files and composing paths (core): declared in the public adem/output.h, written
 * here in the core so that the input layer can read files too. */
#ifndef ADEM_FILES_H
#define ADEM_FILES_H

#include "adem/output.h"

#endif
