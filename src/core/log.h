/* The library's only way to speak: through the hook set by adem_log_set_hook. */
#ifndef ADEM_LOG_H
#define ADEM_LOG_H

#include "adem/base.h"

/* Nested: adem_log_mute(1) silences the log until the matching adem_log_mute(0). Used while a
 * case is loaded again for a stage, so that its warnings are not repeated. */
void adem_log_mute(int on);

#endif
