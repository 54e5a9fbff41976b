#!/usr/bin/env bash
# Packs Debian's Open MPI runtime into a relocatable prefix (default .device/mpi) for a GPU
# machine that lacks Debian's libraries: mpirun (orterun) and orted, libmpi and what it
# loads, the MCA components a one-host job uses (those needing InfiniBand, libfabric, UCX,
# PSM or Java are left out), PMIx's plugins and the help texts. Use it with
#   source .device/mpi/env.sh      (sets OPAL_PREFIX, PMIX_PREFIX, PATH, LD_LIBRARY_PATH)
#   mpirun --allow-run-as-root -np 2 .device/bin/pathtracer ...
set -euo pipefail
cd "$(dirname "$0")/.."
P="${1:-.device/mpi}"
ARCH=lib/x86_64-linux-gnu
rm -rf "$P"
mkdir -p "$P/bin" "$P/lib" "$P/$ARCH/openmpi/lib/openmpi3" "$P/$ARCH/pmix2/lib/pmix" \
         "$P/share/openmpi" "$P/$ARCH/pmix2/share/pmix" "$P/etc"

# Libraries every Linux host has, which are not copied.
BASE='^(linux-vdso|libc|libm|libdl|libpthread|librt|ld-linux-x86-64|libgcc_s|libstdc\+\+)\.so'
# Components for fabrics a one-host job does not use: their libraries stay behind too.
FABRIC='libfabric|libucp|libuct|libucs|libucm|libibverbs|librdmacm|libpsm|libjvm|libmpi_java'

copy_deps() {  # copies what the given ELF files load into $P/lib
  ldd "$@" 2>/dev/null | awk '/=>/ && $3 ~ /^\// {print $1, $3}' | sort -u |
    while read -r name path; do
      [[ "$name" =~ $BASE ]] || cp -L "$path" "$P/lib/$name"
    done
}

cp -L /usr/bin/orterun /usr/bin/orted /usr/bin/ompi_info "$P/bin/"
ln -s orterun "$P/bin/mpirun"
ln -s orterun "$P/bin/mpiexec"
copy_deps "$P/bin/orterun" "$P/bin/orted" "$P/bin/ompi_info" /usr/$ARCH/libmpi.so.40

kept=0 skipped=0
for c in /usr/$ARCH/openmpi/lib/openmpi3/*.so; do
  if ldd "$c" 2>/dev/null | grep -Eq "$FABRIC"; then
    skipped=$((skipped + 1))
    continue
  fi
  cp -L "$c" "$P/$ARCH/openmpi/lib/openmpi3/"
  copy_deps "$c"
  kept=$((kept + 1))
done
cp -L /usr/$ARCH/pmix2/lib/pmix/*.so "$P/$ARCH/pmix2/lib/pmix/"
copy_deps /usr/$ARCH/pmix2/lib/pmix/*.so
cp /usr/share/openmpi/*.txt "$P/share/openmpi/" 2>/dev/null || true
cp /usr/$ARCH/pmix2/share/pmix/*.txt "$P/$ARCH/pmix2/share/pmix/" 2>/dev/null || true
[ -f /etc/openmpi/openmpi-mca-params.conf ] && cp /etc/openmpi/openmpi-mca-params.conf "$P/etc/"

cat > "$P/env.sh" <<'EOF'
# Source this to run the packed Open MPI from wherever it lies.
MPI_PACK="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export OPAL_PREFIX="$MPI_PACK"
export PMIX_PREFIX="$MPI_PACK/lib/x86_64-linux-gnu/pmix2"
export PATH="$MPI_PACK/bin:$PATH"
export LD_LIBRARY_PATH="$MPI_PACK/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export OMPI_MCA_mca_base_component_show_load_errors=0
EOF
echo "pack_mpi: $P: $kept components ($skipped fabric ones left out), $(ls "$P/lib" | wc -l) libraries, $(du -sh "$P" | cut -f1)"
