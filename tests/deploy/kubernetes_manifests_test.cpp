// deploy/k8s/, checked offline — there is no cluster here, and kubectl validates fields only
// against a server's OpenAPI document (`kubectl apply --dry-run=client` still asks the server
// for it; `--validate=false` checks nothing), so:
// 1. the schema: every document against the Kubernetes OpenAPI schema of its kind, unknown
//    fields included (tests/tools/kubernetes_schema_check.cjs on npm's kubernetes-models);
// 2. `kubectl kustomize deploy/k8s` builds the set offline (its resources parse, none twice);
// 3. what deploy/README.md promises, checked across the documents: probes on the side port
//    (/readyz, /healthz), a preStop drain inside the grace period, requests and limits, the
//    token from a Secret, the store on a ReadWriteMany claim, the Service and the budget
//    selecting the pods, the scrape annotations on the metrics port, the Indexed Job's
//    --shard I/N with N its completions, and sweepd's own flag parser accepting the args.
// Each part skips, saying why, where its tool is missing (node and the npm packages come from
// deploy/install-deps.sh; kubectl is not a Debian 12 package this project installs).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "server/config.h"
#include "tests/deploy/shell_command.h"
#include "tests/server/daemon_process.h"
#include "tests/server/http_probe.h"

namespace sweepd::test {
namespace {

using nlohmann::json;

const fs::path kSource = SWEEPD_SOURCE_DIR;
const fs::path kManifests = kSource / "deploy" / "k8s";
const fs::path kNodeModules = kSource / ".tools" / "node_modules";

std::string manifest_files() {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(kManifests)) {
    if (entry.path().extension() == ".yaml" && entry.path().filename() != "kustomization.yaml") {
      names.push_back("'" + entry.path().string() + "'");
    }
  }
  std::sort(names.begin(), names.end());
  std::string list;
  for (const std::string& name : names) list += " " + name;
  return list;
}

// The schema check's output: [{file, object}], or why it could not run.
struct SchemaCheck {
  json documents;
  std::string skip_reason;
  CommandResult run;
};

SchemaCheck schema_check() {
  if (!have_program("node")) return {{}, "node is not on PATH; the schema check cannot run", {}};
  if (!fs::exists(kNodeModules / "kubernetes-models")) {
    return {{}, "kubernetes-models is not installed in .tools/ (run deploy/install-deps.sh)", {}};
  }
  SchemaCheck check;
  check.run =
      run_command("node '" + (kSource / "tests/tools/kubernetes_schema_check.cjs").string() +
                  "' '" + kNodeModules.string() + "'" + manifest_files());
  check.documents = json::parse(check.run.output, nullptr, false);
  return check;
}

const json* find_kind(const json& documents, const std::string& kind) {
  for (const json& document : documents) {
    if (document["object"]["kind"] == kind) return &document["object"];
  }
  return nullptr;
}

// The value after `flag` in args ("--flag", "value"), empty when absent.
std::string flag_value(const json& args, const std::string& flag) {
  for (std::size_t i = 0; i + 1 < args.size(); ++i) {
    if (args[i] == flag) return args[i + 1];
  }
  return "";
}

int container_port(const json& container, const json& port) {
  if (port.is_number()) return port;
  for (const json& declared : container["ports"]) {
    if (declared["name"] == port) return declared["containerPort"];
  }
  return -1;
}

TEST(KubernetesManifests, EveryDocumentMatchesTheKubernetesSchema) {
  const SchemaCheck check = schema_check();
  if (!check.skip_reason.empty()) GTEST_SKIP() << check.skip_reason;
  ASSERT_EQ(check.run.exit_code, 0) << check.run.output;
  ASSERT_TRUE(check.documents.is_array()) << check.run.output;
  EXPECT_EQ(check.documents.size(), 6u);
}

TEST(KubernetesManifests, SchemaCheckFindsMistakes) {
  if (!have_program("node") || !fs::exists(kNodeModules / "kubernetes-models")) {
    GTEST_SKIP() << "node or kubernetes-models missing (run deploy/install-deps.sh)";
  }
  const fs::path directory = fresh_directory("k8s_mistakes");
  std::ofstream(directory / "bad.yaml") << R"(apiVersion: apps/v1
kind: Deployment
metadata: {name: x}
spec:
  replicas: three
  selector: {matchLabels: {app: x}}
  template:
    metadata: {labels: {app: x}}
    spec:
      containers:
        - name: x
          image: x
          readinesProbe: {httpGet: {path: /readyz, port: 9464}}
)";
  const CommandResult run =
      run_command("node '" + (kSource / "tests/tools/kubernetes_schema_check.cjs").string() +
                  "' '" + kNodeModules.string() + "' '" + (directory / "bad.yaml").string() + "'");
  fs::remove_all(directory);
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("/spec/replicas: type"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("/spec/template/spec/containers/0/readinesProbe: unknown field"),
            std::string::npos)
      << run.output;
}

TEST(KubernetesManifests, KustomizeBuildsTheSetOffline) {
  if (!have_program("kubectl")) {
    GTEST_SKIP() << "kubectl is not on PATH (Debian 12's kubernetes-client is kubectl 1.20; "
                    "this project does not install it)";
  }
  const CommandResult run = run_command("kubectl kustomize '" + kManifests.string() + "'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  for (const char* kind : {"kind: Deployment", "kind: Service", "kind: PodDisruptionBudget",
                           "kind: PersistentVolumeClaim"}) {
    EXPECT_NE(run.output.find(kind), std::string::npos) << kind;
  }
}

class KubernetesManifestsAgree : public ::testing::Test {
 protected:
  void SetUp() override {
    const SchemaCheck check = schema_check();
    if (!check.skip_reason.empty()) GTEST_SKIP() << check.skip_reason;
    ASSERT_EQ(check.run.exit_code, 0) << check.run.output;
    documents_ = check.documents;
    const json* deployment = find_kind(documents_, "Deployment");
    ASSERT_NE(deployment, nullptr);
    deployment_ = *deployment;
    pod_ = deployment_["spec"]["template"];
    container_ = pod_["spec"]["containers"][0];
  }

  // The PersistentVolumeClaim called `name`, or null.
  json claim(const std::string& name) const {
    for (const json& document : documents_) {
      const json& object = document["object"];
      if (object["kind"] == "PersistentVolumeClaim" && object["metadata"]["name"] == name) {
        return object;
      }
    }
    return nullptr;
  }
  // The mount path of the pod volume that satisfies `matches`, or "".
  template <typename Match>
  std::string mount_of(const json& pod_spec, const json& container, Match matches) const {
    for (const json& volume : pod_spec["volumes"]) {
      if (!matches(volume)) continue;
      for (const json& mount : container["volumeMounts"]) {
        if (mount["name"] == volume["name"]) return mount["mountPath"];
      }
    }
    return "";
  }

  json documents_, deployment_, pod_, container_;
};

TEST_F(KubernetesManifestsAgree, ProbesAskTheSidePortThatSweepdListensOn) {
  const json& args = container_["args"];
  const std::string http_listen = flag_value(args, "--http-listen");
  ASSERT_FALSE(http_listen.empty());
  const int http_port = std::stoi(http_listen.substr(http_listen.rfind(':') + 1));
  EXPECT_EQ(container_["readinessProbe"]["httpGet"]["path"], "/readyz");
  EXPECT_EQ(container_port(container_, container_["readinessProbe"]["httpGet"]["port"]), http_port);
  EXPECT_EQ(container_["livenessProbe"]["httpGet"]["path"], "/healthz");
  EXPECT_EQ(container_port(container_, container_["livenessProbe"]["httpGet"]["port"]), http_port);
  EXPECT_EQ(pod_["metadata"]["annotations"]["prometheus.io/scrape"], "true");
  EXPECT_EQ(pod_["metadata"]["annotations"]["prometheus.io/port"], std::to_string(http_port));
  EXPECT_EQ(pod_["metadata"]["annotations"]["prometheus.io/path"], "/metrics");
  EXPECT_EQ(container_port(container_, "sweepd"), std::stoi(flag_value(args, "--port")));
}

TEST_F(KubernetesManifestsAgree, SweepdAcceptsTheArgs) {
  const fs::path token_file = fresh_directory("k8s_args") / "token";
  std::ofstream(token_file) << "stand-in";
  std::vector<std::string> args;
  const json& declared = container_["args"];
  for (std::size_t i = 0; i < declared.size(); ++i) {
    std::string arg = declared[i];
    if (arg == "--token-file") {  // the Secret's file exists only in the pod: a stand-in
      args.push_back(arg);
      args.push_back(token_file.string());
      ++i;
      continue;
    }
    if (arg == "$(SWEEPD_WORKERS)") arg = "4";  // Kubernetes expands it from the CPU limit
    args.push_back(arg);
  }
  const std::vector<std::string_view> views(args.begin(), args.end());
  // With the token read, sweepd's start-up rules apply (a token over plain TCP off loopback
  // needs --allow-plaintext or TLS).
  const server::ServerConfig config = server::parse_server_config(views);
  fs::remove_all(token_file.parent_path());
  EXPECT_FALSE(config.token.empty());
  EXPECT_EQ(config.worker_threads, 4);
  EXPECT_EQ(config.port, 7878);
  EXPECT_EQ(config.http_port, 9464);
  EXPECT_EQ(config.listen_address, "0.0.0.0");
  EXPECT_EQ(config.store_dir, "/var/lib/sweepd");
}

TEST_F(KubernetesManifestsAgree, DrainFitsTheGracePeriodAndResourcesAreBounded) {
  const json& pre_stop = container_["lifecycle"]["preStop"]["exec"]["command"];
  ASSERT_EQ(pre_stop.size(), 2u);
  EXPECT_EQ(pre_stop[0], "sleep");
  // The sleep, then sweepd's drain: at most its send timeout (30 s) for a client that reads
  // nothing; the grace period must hold both, or the kubelet kills a draining sweepd.
  const int sleep_seconds = std::stoi(pre_stop[1].get<std::string>());
  EXPECT_GE(pod_["spec"]["terminationGracePeriodSeconds"].get<int>(), sleep_seconds + 30);
  for (const char* kind : {"requests", "limits"}) {
    EXPECT_TRUE(container_["resources"][kind].contains("cpu")) << kind;
    EXPECT_TRUE(container_["resources"][kind].contains("memory")) << kind;
  }
  EXPECT_EQ(deployment_["spec"]["strategy"]["rollingUpdate"]["maxUnavailable"], 0);
}

TEST_F(KubernetesManifestsAgree, TokenComesFromASecretAndTheStoreFromAReadWriteManyClaim) {
  const std::string token_file = flag_value(container_["args"], "--token-file");
  const std::string secret_mount = mount_of(pod_["spec"], container_, [](const json& volume) {
    return volume.contains("secret") && volume["secret"]["secretName"] == "sweepd-token";
  });
  ASSERT_FALSE(secret_mount.empty());
  EXPECT_EQ(token_file, secret_mount + "/token");

  std::string claim_name;
  const std::string store_mount = mount_of(pod_["spec"], container_, [&](const json& volume) {
    if (!volume.contains("persistentVolumeClaim")) return false;
    claim_name = volume["persistentVolumeClaim"]["claimName"];
    return true;
  });
  EXPECT_EQ(flag_value(container_["args"], "--store-dir"), store_mount);
  const json store = claim(claim_name);
  ASSERT_FALSE(store.is_null()) << "no PersistentVolumeClaim " << claim_name;
  EXPECT_EQ(store["spec"]["accessModes"], json::array({"ReadWriteMany"}));
}

TEST_F(KubernetesManifestsAgree, ServiceAndBudgetSelectThePods) {
  const json& labels = pod_["metadata"]["labels"];
  EXPECT_EQ(deployment_["spec"]["selector"]["matchLabels"], labels);
  const json* service = find_kind(documents_, "Service");
  ASSERT_NE(service, nullptr);
  EXPECT_EQ((*service)["spec"]["selector"], labels);
  for (const json& port : (*service)["spec"]["ports"]) {
    EXPECT_GT(container_port(container_, port["targetPort"]), 0) << port.dump();
  }
  const json* budget = find_kind(documents_, "PodDisruptionBudget");
  ASSERT_NE(budget, nullptr);
  EXPECT_EQ((*budget)["spec"]["selector"]["matchLabels"], labels);
}

TEST_F(KubernetesManifestsAgree, RenderJobShardsByCompletionIndexOverTheService) {
  const json* job = find_kind(documents_, "Job");
  ASSERT_NE(job, nullptr);
  EXPECT_EQ((*job)["spec"]["completionMode"], "Indexed");
  const int completions = (*job)["spec"]["completions"];
  const json& render = (*job)["spec"]["template"]["spec"]["containers"][0];
  EXPECT_EQ(render["command"], json::array({"render_frames"}));
  EXPECT_EQ(flag_value(render["args"], "--shard"),
            "$(JOB_COMPLETION_INDEX)/" + std::to_string(completions));
  const json* service = find_kind(documents_, "Service");
  ASSERT_NE(service, nullptr);
  const std::string service_address =
      (*service)["metadata"]["name"].get<std::string>() + ":" +
      std::to_string((*service)["spec"]["ports"][0]["port"].get<int>());
  EXPECT_EQ(flag_value(render["args"], "--server"), service_address);
  // The token from the same Secret as the daemon's, as a file (args show in the process list).
  EXPECT_EQ(flag_value(render["args"], "--token"), "");
  const std::string secret_mount =
      mount_of((*job)["spec"]["template"]["spec"], render, [](const json& volume) {
        return volume.contains("secret") && volume["secret"]["secretName"] == "sweepd-token";
      });
  ASSERT_FALSE(secret_mount.empty());
  EXPECT_EQ(flag_value(render["args"], "--token-file"), secret_mount + "/token");
  std::string work_claim;
  mount_of((*job)["spec"]["template"]["spec"], render, [&](const json& volume) {
    if (!volume.contains("persistentVolumeClaim")) return false;
    work_claim = volume["persistentVolumeClaim"]["claimName"];
    return true;
  });
  const json work = claim(work_claim);
  ASSERT_FALSE(work.is_null()) << "no PersistentVolumeClaim " << work_claim;
  EXPECT_EQ(work["spec"]["accessModes"], json::array({"ReadWriteMany"}));
}

}  // namespace
}  // namespace sweepd::test
