// Offline schema check of Kubernetes manifests (deploy/k8s/), with no cluster: every YAML
// document is validated against the Kubernetes OpenAPI schema of its apiVersion and kind, as
// compiled by the npm package kubernetes-models (its validators are generated from the API's
// OpenAPI spec: types, formats, required fields, enums), and any field the schema does not
// know (a typo such as `readinesProbe`) is reported too: the document is handed to the
// validator through a Proxy that records which fields it reads, and a field it never reads is
// unknown to the schema.
//
// Usage: node kubernetes_schema_check.cjs NODE_MODULES FILE.yaml...
//   NODE_MODULES: where kubernetes-models and yaml are installed (deploy/install-deps.sh puts
//   them in .tools/node_modules). Prints the documents as one JSON array on stdout and exits 0
//   when all are valid; otherwise prints each problem (file, document, path, reason) on stderr
//   and exits 1. Exit 2: a usage error or a missing package.
"use strict";
const fs = require("node:fs");
const path = require("node:path");

const [modulesArgument, ...files] = process.argv.slice(2);
const modules = modulesArgument && path.resolve(modulesArgument);
if (!modulesArgument || files.length === 0) {
  console.error("usage: node kubernetes_schema_check.cjs NODE_MODULES FILE.yaml...");
  process.exit(2);
}
let YAML;
try {
  YAML = require(path.join(modules, "yaml"));
  require.resolve(path.join(modules, "kubernetes-models", "package.json"));
} catch (error) {
  console.error(`kubernetes_schema_check: ${error.message}`);
  process.exit(2);
}

// apps/v1 Deployment -> IoK8sApiAppsV1Deployment; v1 Service -> IoK8sApiCoreV1Service.
function schemaName(apiVersion, kind) {
  const [group, version] = apiVersion.includes("/") ? apiVersion.split("/") : ["core", apiVersion];
  const title = (word) => word.charAt(0).toUpperCase() + word.slice(1);
  return `IoK8sApi${title(group.split(".")[0])}${title(version)}${kind}`;
}

// A read-recording view of `root`: reads[target] is the set of keys the validator looked at.
function recorded(root, reads) {
  const views = new WeakMap();
  const view = (value, where) => {
    if (value === null || typeof value !== "object") return value;
    if (views.has(value)) return views.get(value);
    reads.set(value, { where, keys: new Set() });
    const proxy = new Proxy(value, {
      get(target, key, receiver) {
        const child = Reflect.get(target, key, receiver);
        if (typeof key !== "string" || !Object.prototype.hasOwnProperty.call(target, key)) {
          return child;
        }
        reads.get(target).keys.add(key);
        return view(child, `${where}/${key}`);
      },
      getOwnPropertyDescriptor(target, key) {
        if (typeof key === "string") reads.get(target).keys.add(key);
        return Reflect.getOwnPropertyDescriptor(target, key);
      },
    });
    views.set(value, proxy);
    return proxy;
  };
  return view(root, "");
}

const problems = [];
const documents = [];
for (const file of files) {
  const parsed = YAML.parseAllDocuments(fs.readFileSync(file, "utf8"));
  parsed.forEach((doc, index) => {
    const where = `${file}, document ${index + 1}`;
    for (const error of doc.errors) problems.push(`${where}: YAML: ${error.message}`);
    const object = doc.toJS();
    if (object === null) return;
    if (!object.apiVersion || !object.kind) {
      problems.push(`${where}: no apiVersion or kind`);
      return;
    }
    const name = schemaName(object.apiVersion, object.kind);
    let validate;
    try {
      ({ validate } = require(path.join(modules, "kubernetes-models", "_schemas", `${name}.js`)));
    } catch {
      problems.push(`${where}: no schema for ${object.apiVersion} ${object.kind}`);
      return;
    }
    const reads = new Map();
    if (!validate(recorded(object, reads))) {
      for (const error of validate.errors) {
        problems.push(`${where}: ${error.instancePath || "/"}: ${error.keyword} ${JSON.stringify(error.params)}`);
      }
    }
    for (const [target, { where: at, keys }] of reads) {
      if (Array.isArray(target)) continue;
      for (const key of Object.keys(target)) {
        if (!keys.has(key)) problems.push(`${where}: ${at}/${key}: unknown field`);
      }
    }
    documents.push({ file: path.basename(file), object });
  });
}
if (problems.length > 0) {
  for (const problem of problems) console.error(problem);
  process.exit(1);
}
process.stdout.write(JSON.stringify(documents));
