#!/bin/sh
# Rename only: one stem per concept in every tracked source, test, binding and doc (issue 28):
#   collisions   adem_collision_* -> adem_collide_* (types; the functions were adem_collide_*),
#                adem_default_collision_spec -> adem_default_collide_spec,
#                ADEM_COLLISION_* -> ADEM_COLLIDE_*, and the function adem_collide_params ->
#                adem_collide_derive (its name is now the type's, adem_collide_params)
#   validations  adem_validate_* -> adem_validation_* (adem_validation_run, _path, _plot)
#   files        adem_fileio_* -> adem_file_* (the atomic writes beside adem_file_read_all)
# Idempotent: run it again on a tree that gained new files (a merge) and it renames what is left.
#   scripts/rename-stems.sh    (from anywhere in the checkout)
set -eu
cd "$(git rev-parse --show-toplevel)"
# Every tracked text file that names an old stem, but this script.
git ls-files -z -- '*.c' '*.h' '*.py' '*.md' '*.txt' '*.cmake' '*.sh' '*.yaml' ':!scripts/rename-stems.sh' |
  xargs -0 grep -lZE 'adem_collision_|adem_default_collision_spec|ADEM_COLLISION_|adem_collide_params|adem_validate_|adem_fileio_' |
  xargs -0 -r sed -i -E \
    -e 's/\badem_collide_params[[:space:]]*\(/adem_collide_derive(/g' \
    -e 's/\badem_collision_/adem_collide_/g' \
    -e 's/\badem_default_collision_spec\b/adem_default_collide_spec/g' \
    -e 's/\bADEM_COLLISION_/ADEM_COLLIDE_/g' \
    -e 's/\badem_validate_/adem_validation_/g' \
    -e 's/\badem_fileio_/adem_file_/g'
