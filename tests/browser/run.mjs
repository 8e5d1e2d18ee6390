// Runs one browser test file with Node's test runner (spec reporter), after checking that the npm
// packages of package.json are installed: `npm ci --prefix tests/browser` (tools/dev test does it).
import { existsSync } from 'node:fs';
import { spawnSync } from 'node:child_process';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
if (!existsSync(path.join(here, 'node_modules', 'playwright-core', 'package.json'))) {
  console.error(`browser tests: playwright-core is not installed; run: npm ci --prefix ${here}`);
  process.exit(1);
}
const r = spawnSync(process.execPath, ['--test', '--test-reporter=spec', process.argv[2]], { stdio: 'inherit' });
process.exit(r.status ?? 1);
