/* The library's only way to speak: through the hook set by adem_log_set_hook. */
#ifndef ADEM_LOG_H
#define ADEM_LOG_H

#include "adem/adem.h"

#if defined(__GNUC__)
#define ADEM_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define ADEM_PRINTF(a, b)
#endif

void adem_log(adem_log_level level, const char *fmt, ...) ADEM_PRINTF(2, 3);
/* Nested: adem_log_mute(1) silences the log until the matching adem_log_mute(0). Used while a
 * case is loaded again for a stage, so that its warnings are not repeated. */
void adem_log_mute(int on);
/* Fills err (if not NULL) and returns its status. */
adem_status adem_error_set(adem_error *err, adem_status status, const char *fmt, ...) ADEM_PRINTF(3, 4);

#endif
