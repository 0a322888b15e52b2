#!/usr/bin/env bash
# Rebuild viewer.min.js: three.js (npm, MIT) and src/viewer.js bundled and minified by esbuild
# (npm). The versions are pinned in package.json / package-lock.json; the output is committed
# and inlined into every page `ccrkit view` writes (src/export/view/), so no build step is needed
# to use ccrkit. Run after changing src/viewer.js: `bash assets/viewer/build.sh`.
set -euo pipefail
cd "$(dirname "$0")"
npm ci --no-audit --no-fund
{
  echo "/*! ccrkit viewer: src/viewer.js and three.js $(node -p "JSON.parse(require('fs').readFileSync('node_modules/three/package.json')).version") (https://threejs.org), whose licence follows."
  sed 's/^/ * /' node_modules/three/LICENSE
  echo " */"
} > banner.txt
npx esbuild src/viewer.js --bundle --minify --format=iife --target=es2020 \
  --legal-comments=none --banner:js="$(cat banner.txt)" --outfile=viewer.min.js
rm banner.txt
ls -l viewer.min.js
