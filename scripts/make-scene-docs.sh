#!/usr/bin/env bash
# Regenerates the listings in docs/scenes.md from `traverse check` (keeps the text above them).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
exe=${1:-$here/build/traverse}
doc=$here/docs/scenes.md
head=$(sed -n '1,/^## The default scene, every key/p' "$doc")
{
  printf '%s\n\n```yaml\n' "$head"
  "$exe" check "$here/inputs/default.yaml" | tail -n +2
  printf '```\n\n## The cantilever beam scene, every key\n\n```yaml\n'
  "$exe" check "$here/inputs/beam/cantilever.yaml" | tail -n +2
  printf '```\n\n## Registered types\n\n```\n'
  "$exe" check "$here/inputs/default.yaml" --types | sed -n '/^# cross-section types/,$p'
  printf '```\n'
} > "$doc.tmp"
mv "$doc.tmp" "$doc"
