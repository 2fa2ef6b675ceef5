#!/bin/sh
# rss.sh PREFIX COMMAND [ARGS...]: runs COMMAND under GNU time (/usr/bin/time -v) and writes its
# report, with the peak resident set size, to PREFIX.RANK (RANK = the MPI rank, 0 outside MPI).
# run_peers.sh puts it between mpirun and the code, so every rank gets its own report.
prefix=$1
shift
rank=${OMPI_COMM_WORLD_RANK:-${PMI_RANK:-${PMIX_RANK:-0}}}
exec /usr/bin/time -v -o "$prefix.$rank" "$@"
