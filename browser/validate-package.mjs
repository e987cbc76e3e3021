// Validates an engine package's JSON against the JSON Schemas the package ships
// (nimbus-package.schema.json for nimbus-package.json, nimbus-uniforms.schema.json for every
// uniforms/*.json), with Ajv, a validator independent of the Rust types the schemas come from.
// Usage: node validate-package.mjs DIR. Prints one JSON line per file ({ file, valid, errors })
// and exits 1 when any file is invalid.
import { readFileSync, readdirSync } from 'node:fs';
import { join } from 'node:path';
import Ajv2020 from 'ajv/dist/2020.js';

const dir = process.argv[2];
if (!dir) {
  console.error('usage: node validate-package.mjs DIR');
  process.exit(2);
}
const read = (file) => JSON.parse(readFileSync(join(dir, file), 'utf8'));
// strict: an unknown keyword in a schema is an error too, not silently ignored.
const ajv = new Ajv2020({ allErrors: true, strict: true });
// The numeric formats schemars writes for Rust's integer and float types, checked for what
// they mean.
const integer = (bits) => (x) => Number.isInteger(x) && x >= 0 && x < 2 ** bits;
for (const [name, check] of [
  ['uint', integer(64)],
  ['uint16', integer(16)],
  ['uint32', integer(32)],
  ['uint64', integer(64)],
  ['double', Number.isFinite],
  ['float', Number.isFinite],
]) {
  ajv.addFormat(name, { type: 'number', validate: check });
}
const checks = [['nimbus-package.json', 'nimbus-package.schema.json']];
for (const f of readdirSync(join(dir, 'uniforms')).sort()) {
  if (f.endsWith('.json')) checks.push([join('uniforms', f), 'nimbus-uniforms.schema.json']);
}
const validators = new Map();
let invalid = 0;
for (const [file, schemaFile] of checks) {
  if (!validators.has(schemaFile)) validators.set(schemaFile, ajv.compile(read(schemaFile)));
  const validate = validators.get(schemaFile);
  const valid = validate(read(file));
  if (!valid) invalid += 1;
  console.log(JSON.stringify({ file, valid, errors: valid ? [] : validate.errors }));
}
process.exit(invalid ? 1 : 0);
