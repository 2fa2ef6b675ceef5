/* Reproductions of the irazabal paper: registered here, implemented by the issue that adds them. */
#include "validate.h"

const adem_validation adem_validations_irazabal[] = {{NULL, NULL, NULL, NULL}};
const size_t adem_validations_irazabal_count = 0;
