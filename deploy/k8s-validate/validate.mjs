// Validates deploy/k8s offline, with no cluster: each manifest against the
// Kubernetes API schemas (kubernetes-models), then that the manifests agree
// with each other, with the image and with armature-server; and
// deploy/compose.yaml's essentials.
//
//   node validate.mjs [--env-names FILE]
// FILE lists the ARMATURE_* variables armature-server reads (from its
// --help), so every ConfigMap key is checked to be a real setting.
import { readFileSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";
import { parseAllDocuments, parse } from "yaml";
import { ConfigMap } from "kubernetes-models/v1/ConfigMap";
import { PersistentVolumeClaim } from "kubernetes-models/v1/PersistentVolumeClaim";
import { Service } from "kubernetes-models/v1/Service";
import { Deployment } from "kubernetes-models/apps/v1/Deployment";
import { HorizontalPodAutoscaler } from "kubernetes-models/autoscaling/v2/HorizontalPodAutoscaler";
import { PodDisruptionBudget } from "kubernetes-models/policy/v1/PodDisruptionBudget";

const here = dirname(fileURLToPath(import.meta.url));
const k8sDir = join(here, "..", "k8s");
const models = {
  "v1/ConfigMap": ConfigMap,
  "v1/PersistentVolumeClaim": PersistentVolumeClaim,
  "v1/Service": Service,
  "apps/v1/Deployment": Deployment,
  "autoscaling/v2/HorizontalPodAutoscaler": HorizontalPodAutoscaler,
  "policy/v1/PodDisruptionBudget": PodDisruptionBudget,
};

const failures = [];
function check(ok, what) {
  console.log(`${ok ? "ok  " : "FAIL"} ${what}`);
  if (!ok) failures.push(what);
}

// Schema validation of one object; returns the error text or "".
function schemaErrors(object) {
  const Model = models[`${object.apiVersion}/${object.kind}`];
  if (!Model) return `no schema for ${object.apiVersion} ${object.kind}`;
  try {
    new Model(object).validate();
    return "";
  } catch (e) {
    return e.message;
  }
}

// The validator must be able to fail: a Deployment with a wrong type is refused.
const broken = { apiVersion: "apps/v1", kind: "Deployment", metadata: { name: "x" },
  spec: { replicas: "two", selector: {}, template: { spec: { containers: [{ name: "c", ports: [{ containerPort: "grpc" }] }] } } } };
check(schemaErrors(broken) !== "", "the schema check refuses a malformed Deployment");

// Every resource the kustomization lists, schema-checked.
const kustomization = parse(readFileSync(join(k8sDir, "kustomization.yaml"), "utf8"));
const objects = [];
for (const file of kustomization.resources) {
  for (const doc of parseAllDocuments(readFileSync(join(k8sDir, file), "utf8"))) {
    if (doc.errors.length) {
      check(false, `${file}: YAML: ${doc.errors[0].message}`);
      continue;
    }
    const object = doc.toJS();
    if (!object) continue;
    const errors = schemaErrors(object);
    check(errors === "", `${file}: ${object.kind} ${object.metadata?.name} matches the API schema${errors ? ": " + errors : ""}`);
    objects.push(object);
  }
}
const kinds = new Set(objects.map((o) => o.kind));
for (const kind of ["Deployment", "Service", "HorizontalPodAutoscaler", "PodDisruptionBudget", "ConfigMap"])
  check(kinds.has(kind), `a ${kind} is deployed`);

const find = (kind, name) => objects.find((o) => o.kind === kind && (!name || o.metadata.name === name));
const matches = (selector, labels) => Object.entries(selector ?? {}).every(([k, v]) => labels?.[k] === v);

const deployment = find("Deployment");
const pod = deployment.spec.template;
const container = pod.spec.containers[0];
const portNumber = (name) => container.ports.find((p) => p.name === name)?.containerPort;
check(matches(deployment.spec.selector.matchLabels, pod.metadata.labels), "the Deployment's selector matches its pods");

// Probes: grpc health on the gRPC port.
for (const probe of ["startupProbe", "readinessProbe", "livenessProbe"])
  check(container[probe]?.grpc?.port === portNumber("grpc"), `${probe} is a grpc probe on the gRPC port`);
check(container.resources?.requests?.cpu && container.resources?.requests?.memory &&
      container.resources?.limits?.cpu && container.resources?.limits?.memory, "resource requests and limits are set");

// Settings: envFrom the ConfigMap, whose keys armature-server knows.
const configMap = find("ConfigMap");
check(container.envFrom?.some((e) => e.configMapRef?.name === configMap.metadata.name), "the container takes the ConfigMap with envFrom");
const config = configMap.data;
check(Number(config.ARMATURE_GRPC_PORT) === portNumber("grpc"), "ARMATURE_GRPC_PORT is the container's grpc port");
check(Number(config.ARMATURE_HTTP_PORT) === portNumber("http"), "ARMATURE_HTTP_PORT is the container's http port");
const envNamesFlag = process.argv.indexOf("--env-names");
if (envNamesFlag > 0) {
  const known = new Set(readFileSync(process.argv[envNamesFlag + 1], "utf8").split(/\s+/).filter(Boolean));
  for (const key of Object.keys(config)) check(known.has(key), `ConfigMap key ${key} is a setting of armature-server`);
}
const grace = Number(config.ARMATURE_SHUTDOWN_GRACE);
const preStop = Number(container.lifecycle?.preStop?.exec?.command?.[1] ?? 0);
check(grace + preStop < pod.spec.terminationGracePeriodSeconds, "the shutdown grace fits in terminationGracePeriodSeconds");

// Store: an S3 bucket (ARMATURE_STORE), credentials from a Secret, the data dir a per-pod cache.
check(/^s3(\+https)?:\/\/[^/:]+(:\d+)?\/[a-z0-9][a-z0-9.-]{1,61}[a-z0-9](\/|$)/.test(config.ARMATURE_STORE ?? ""),
      "ARMATURE_STORE names an S3 endpoint and bucket");
check(container.envFrom?.some((e) => e.secretRef?.name === "armature-s3" && !e.secretRef.optional),
      "the S3 credentials come from the Secret armature-s3");
const secretExample = parse(readFileSync(join(k8sDir, "s3-secret.example.yaml"), "utf8"));
check(secretExample.kind === "Secret" && secretExample.metadata.name === "armature-s3" &&
      ["AWS_ACCESS_KEY_ID", "AWS_SECRET_ACCESS_KEY"].every((k) => k in (secretExample.stringData ?? {})),
      "s3-secret.example.yaml shows the Secret's keys");
check(!kustomization.resources.includes("s3-secret.example.yaml"), "no placeholder Secret is applied");
const cacheVolume = pod.spec.volumes.find((v) => v.name === "data");
check(Boolean(cacheVolume?.emptyDir) &&
      container.volumeMounts.some((m) => m.name === "data" && m.mountPath === config.ARMATURE_DATA_DIR),
      "the bucket's cache is an emptyDir mounted at ARMATURE_DATA_DIR");

// The RWX variant (rwx/): the shared ReadWriteMany claim instead of the bucket.
const rwxDir = join(k8sDir, "rwx");
const rwx = parse(readFileSync(join(rwxDir, "kustomization.yaml"), "utf8"));
const pvc = parse(readFileSync(join(rwxDir, "pvc.yaml"), "utf8"));
check(schemaErrors(pvc) === "", "rwx/pvc.yaml matches the API schema");
check(pvc.spec.accessModes.includes("ReadWriteMany"), "the rwx claim is ReadWriteMany, so replicas share it");
check(rwx.resources.includes("..") && rwx.resources.includes("pvc.yaml"), "rwx/ is the base plus the claim");
const rwxPatches = (rwx.patches ?? []).map((p) => ({ target: p.target, ops: parse(p.patch) }));
const volumeOp = rwxPatches.flatMap((p) => p.ops).find((op) => op.path === "/spec/template/spec/volumes/0");
check(volumeOp?.value?.persistentVolumeClaim?.claimName === pvc.metadata.name && volumeOp?.value?.name === "data",
      "rwx/ mounts the claim as the data volume");
check(rwxPatches.some((p) => p.target.kind === "ConfigMap" && p.ops.some((op) => op.op === "remove" && op.path === "/data/ARMATURE_STORE")),
      "rwx/ drops ARMATURE_STORE");
check(pod.spec.securityContext?.runAsNonRoot === true && pod.spec.securityContext?.runAsUser === 10001,
      "pods run as the image's non-root user (10001)");

// Services, HPA and PDB select or target the Deployment's pods.
const services = objects.filter((o) => o.kind === "Service");
for (const port of ["grpc", "http"])
  check(services.some((s) => matches(s.spec.selector, pod.metadata.labels) && s.spec.ports.some((p) => p.targetPort === port)),
        `a Service routes to the ${port} port`);
const hpa = find("HorizontalPodAutoscaler");
check(hpa.spec.scaleTargetRef.kind === "Deployment" && hpa.spec.scaleTargetRef.name === deployment.metadata.name,
      "the HPA scales the Deployment");
check(hpa.spec.minReplicas >= 2, "the HPA keeps at least two replicas");
check(deployment.spec.replicas === undefined, "the Deployment leaves the replica count to the HPA");
const pdb = find("PodDisruptionBudget");
check(matches(pdb.spec.selector.matchLabels, pod.metadata.labels), "the PDB covers the Deployment's pods");
check(kustomization.images?.some((i) => i.name === container.image.split(":")[0]), "kustomization.yaml sets the image");

// Compose: the server with its data volume and both ports.
const compose = parse(readFileSync(join(here, "..", "compose.yaml"), "utf8"));
const service = compose.services?.armature;
check(Boolean(service), "compose.yaml has the armature service");
check(service?.build?.dockerfile === "deploy/Dockerfile", "compose builds deploy/Dockerfile");
for (const port of ["50051", "8080"])
  check(service?.ports?.some((p) => String(p).endsWith(`:${port}`)), `compose publishes port ${port}`);
check(service?.volumes?.some((v) => String(v).endsWith(":/var/lib/armature/data") && compose.volumes?.[String(v).split(":")[0]] !== undefined),
      "compose keeps the data dir (the bucket's cache) on a named volume");
check(/^s3:\/\/minio:9000\//.test(service?.environment?.ARMATURE_STORE ?? "") && Boolean(compose.services?.minio),
      "compose keeps the assets on its MinIO's bucket");

console.log(`${failures.length} failed`);
process.exit(failures.length ? 1 : 0);
