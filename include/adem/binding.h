/* What a program that cannot read C structs (a Python module over libadem.so through ctypes)
 * needs beside the rest of the API: the fields of a loaded case it sets or reads, and the sizes
 * of the public structs it mirrors, so that it can refuse to load a library whose layout is not
 * the one it was written for. */
#ifndef ADEM_BINDING_H
#define ADEM_BINDING_H

#include <stddef.h>

#include "adem/base.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct adem_world adem_world; /* adem/world.h */
typedef struct adem_case adem_case;   /* adem/case.h */

/* The case's world (owned by the case). */
adem_world *adem_case_world(adem_case *c);
/* Output folder of the case's run (adem run --out). */
adem_status adem_case_set_output_dir(adem_case *c, const char *dir, adem_error *err);
const char *adem_case_output_dir(const adem_case *c);
double adem_case_end_time(const adem_case *c);
const char *adem_case_name(const adem_case *c);

/* sizeof the public struct or enum named type ("adem_material_def", ...); 0 for a name it does
 * not know. */
size_t adem_abi_sizeof(const char *type);

#ifdef __cplusplus
}
#endif
#endif
