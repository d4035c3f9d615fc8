# Sourced by the plot scripts: `column NAME` prints the 1-based index of the column NAME in the
# header of "$csv" (`firelook bench --csv` owns the order), or stops the script naming the file.
column() {
  local n
  n=$(head -n 1 "$csv" | tr ',' '\n' | grep -nx "$1" | cut -d: -f1)
  [[ -n "$n" ]] || { echo "$(basename "$0"): $csv has no column '$1'" >&2; exit 2; }
  echo "$n"
}
