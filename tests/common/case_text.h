/* Text helpers for tests on case files and messages: derive a case by one replacement, look for
 * words in a message. Include after cmocka.h. */
#ifndef ADEM_TEST_CASE_TEXT_H
#define ADEM_TEST_CASE_TEXT_H

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* TEXT with the first FROM replaced by TO, as a fresh string (free it); fails if FROM is absent. */
static inline char *replaced(const char *text, const char *from, const char *to) {
  const char *at = strstr(text, from);
  if (!at) fail_msg("'%s' not in the case text", from);
  size_t n = strlen(text) - strlen(from) + strlen(to) + 1;
  char *s = malloc(n);
  assert_non_null(s);
  snprintf(s, n, "%.*s%s%s", (int)(at - text), text, to, at + strlen(from));
  return s;
}

/* Whether TEXT contains WORD, ignoring case. */
static inline int mentions(const char *text, const char *word) {
  size_t n = strlen(word);
  for (const char *s = text; *s; ++s) {
    size_t k = 0;
    while (k < n && s[k] && tolower((unsigned char)s[k]) == tolower((unsigned char)word[k])) ++k;
    if (k == n) return 1;
  }
  return 0;
}

/* Fails, quoting TEXT, unless TEXT contains WORD ignoring case. */
#define assert_mentions(text, word)                                     \
  do {                                                                  \
    if (!mentions(text, word)) fail_msg("'%s' not in: %s", word, text); \
  } while (0)

/* Fails, quoting TEXT, unless TEXT contains WORD exactly (case counts). */
#define assert_contains(text, word)                                           \
  do {                                                                        \
    if (!strstr((text), (word))) fail_msg("'%s' not in: %s", (word), (text)); \
  } while (0)

#endif
