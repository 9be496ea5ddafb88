// deploy/kubernetes validated offline, as CI can (no cluster is reachable): each overlay built with
// `kubectl kustomize`, every object checked against the Kubernetes API's OpenAPI schemas
// (kubernetes-models ships them, with ajv), then what Tessera's pods need checked by hand: gRPC
// probes on the gRPC port, resource requests, the token and the store from Secrets, a headless
// Service, a disruption budget and an autoscaler for the Deployment, one GPU per pod in the gpu
// overlay and none in the cpu one.
// Usage: node validate.mjs KUSTOMIZE_DIR... (e.g. deploy/kubernetes/overlays/cpu)
import { execFileSync } from 'node:child_process';
import { parseAllDocuments } from 'yaml';

const failures = [];
const check = (condition, message) => condition || failures.push(message);

// apiVersion "apps/v1" → kubernetes-models/apps/v1/KIND; "v1" → kubernetes-models/v1/KIND.
async function schemaCheck(object, where) {
  const module = await import(`kubernetes-models/${object.apiVersion}/${object.kind}`).catch(() => null);
  if (!module) return failures.push(`${where}: no schema for ${object.apiVersion} ${object.kind}`);
  try {
    new module[object.kind](object).validate();
  } catch (error) {
    failures.push(`${where}: ${error.message}`);
  }
}

function podChecks(deployment, overlay) {
  const pod = deployment.spec.template.spec;
  const server = pod.containers.find((c) => c.name === 'tessera-server');
  check(server, `${overlay}: no tessera-server container`);
  if (!server) return;
  const grpcPort = server.ports.find((p) => p.name === 'grpc')?.containerPort;
  for (const probe of ['startupProbe', 'readinessProbe', 'livenessProbe']) {
    check(server[probe]?.grpc?.port === grpcPort, `${overlay}: ${probe} is not a gRPC probe on port ${grpcPort}`);
  }
  check(server.resources?.requests?.cpu && server.resources?.requests?.memory, `${overlay}: no cpu/memory requests`);
  check(server.resources?.limits?.memory, `${overlay}: no memory limit (the server sizes its budget from it)`);
  const env = Object.fromEntries(server.env.map((e) => [e.name, e]));
  check(env.TESSERA_STORE?.valueFrom?.secretKeyRef, `${overlay}: the store's DSN is not from a Secret`);
  check(env.TESSERA_TOKEN_FILE && pod.volumes.some((v) => v.secret?.secretName === 'tessera-token'),
        `${overlay}: the token is not from a Secret`);
  const drain = Number(env.TESSERA_DRAIN_DELAY?.value ?? 1), grace = Number(env.TESSERA_SHUTDOWN_GRACE?.value ?? 4);
  check(drain >= (server.readinessProbe?.periodSeconds ?? 10),
        `${overlay}: the drain delay must outlast one readiness period, so the pod leaves the Services first`);
  check(drain + grace < (pod.terminationGracePeriodSeconds ?? 30),
        `${overlay}: the server's drain and grace must end before Kubernetes kills the pod`);
  const gpus = server.resources?.limits?.['nvidia.com/gpu'];
  if (overlay.endsWith('gpu')) check(Number(gpus) === 1, `${overlay}: expects one nvidia.com/gpu per pod, got ${gpus}`);
  else check(gpus === undefined, `${overlay}: a CPU pod asks for a GPU`);
  check(server.image === `tessera:${overlay.split('/').pop()}`, `${overlay}: image ${server.image}`);
}

async function validateOverlay(overlay) {
  const text = execFileSync('kubectl', ['kustomize', overlay], { encoding: 'utf8', stdio: ['ignore', 'pipe', 'pipe'] });
  const objects = parseAllDocuments(text).map((d) => d.toJS()).filter(Boolean);
  for (const object of objects) await schemaCheck(object, `${overlay}: ${object.kind}/${object.metadata?.name}`);
  const find = (kind, name) => objects.find((o) => o.kind === kind && o.metadata.name === name);
  const deployment = find('Deployment', 'tessera');
  check(deployment, `${overlay}: no Deployment tessera`);
  if (deployment) podChecks(deployment, overlay);
  check(find('Service', 'tessera-headless')?.spec.clusterIP === 'None', `${overlay}: no headless Service`);
  check(find('PodDisruptionBudget', 'tessera'), `${overlay}: no PodDisruptionBudget`);
  check(find('HorizontalPodAutoscaler', 'tessera')?.spec.scaleTargetRef.name === 'tessera', `${overlay}: no autoscaler`);
  check(find('StatefulSet', 'postgres'), `${overlay}: no PostgreSQL StatefulSet`);
  console.log(`${overlay}: ${objects.length} objects (${objects.map((o) => o.kind).join(', ')})`);
}

for (const overlay of process.argv.slice(2)) await validateOverlay(overlay);
if (failures.length) {
  console.error(`FAILED:\n${failures.join('\n')}`);
  process.exit(1);
}
console.log('kubernetes manifests: OK');
