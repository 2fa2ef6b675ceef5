/* adem reference: the case-file reference as Markdown. */
#include <stdio.h>
#include <string.h>

#include "adem/case.h"
#include "cli.h"

int cmd_reference(int argc, char **argv) {
  if (argc > 0 && (strcmp(argv[0], "-h") == 0 || strcmp(argv[0], "--help") == 0)) {
    puts("Usage: adem reference\n\nPrints the case-file reference (every key with its type, "
         "unit, default,\nrange and meaning) as Markdown on standard output.\n\nExample:\n"
         "  adem reference > case-reference.md");
    return EXIT_OK;
  }
  adem_case_write_reference(stdout);
  return fflush(stdout) == 0 ? EXIT_OK : EXIT_IO;
}
