#!/bin/sh
# Rename only: the core's internal world header src/core/world.h becomes src/core/world_internal.h
# (what it holds: the world's composition, for the layers above and the tests), so that its name
# differs from the public include/adem/world.h, and every include of it follows. Idempotent: run
# it again on a tree that gained new files (a merge) and it renames what is left.
#   scripts/rename-internal-headers.sh    (from anywhere in the checkout)
set -eu
cd "$(git rev-parse --show-toplevel)"
if [ -f src/core/world.h ]; then
  git mv src/core/world.h src/core/world_internal.h
fi
# Internal code includes it as "world.h" (layer include paths); public code as "adem/world.h",
# which this leaves alone.
git ls-files -z -- src tests fuzz bench app | xargs -0 grep -lZ '#include "world\.h"' 2>/dev/null |
  xargs -0 -r sed -i 's|#include "world\.h"|#include "world_internal.h"|'
git ls-files -z -- docs '*.md' src tests | xargs -0 grep -lZ 'src/core/world\.h' 2>/dev/null |
  xargs -0 -r sed -i 's|src/core/world\.h|src/core/world_internal.h|g'
sed -i 's|no module includes world\.h;|no module includes world_internal.h;|' docs/architecture.md
