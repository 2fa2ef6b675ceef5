#include "log.h"

#include <stdarg.h>
#include <stdio.h>

static void default_hook(adem_log_level level, const char *message, void *user) {
  (void)user;
  fprintf(stderr, "%s%s\n", level == ADEM_LOG_WARN ? "adem: warning: " : "adem: ", message);
}

static adem_log_fn *log_hook = default_hook;
static void *log_user = NULL;
static int log_muted = 0;

void adem_log_mute(int on) { log_muted += on ? 1 : -1; }

void adem_log_set_hook(adem_log_fn *fn, void *user) {
  log_hook = fn ? fn : default_hook;
  log_user = user;
}

void adem_log(adem_log_level level, const char *fmt, ...) {
  char buf[ADEM_MSG_MAX];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  if (log_muted > 0) return;
  log_hook(level, buf, log_user);
}

adem_status adem_error_set(adem_error *err, adem_status status, const char *fmt, ...) {
  if (err) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    err->status = status;
  }
  return status;
}
