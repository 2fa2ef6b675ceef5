/* Reproductions of the haervig paper: registered here, implemented by the issue that adds them. */
#include "validate.h"

const adem_validation adem_validations_haervig[] = {{NULL, NULL, NULL, NULL}};
const size_t adem_validations_haervig_count = 0;
