/* Atomic files: declared in the public adem/output.h. */
#ifndef ADEM_FILEIO_H
#define ADEM_FILEIO_H

#include "adem/output.h"
#include "files.h"

#endif
