// mcpose-tools hw-workload: the initial hypotheses of one `mcpose bench` iteration of the paper's
// objects in the hardware raster core's formats, with the C++ model's counts: the real workload
// the RTL testbench replays (scripts/hw.sh workload, docs/hardware.md).
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "cli/common.h"
#include "mcpose/bench.h"
#include "mcpose/dataset.h"
#include "mcpose/io_util.h"
#include "tools.h"

namespace mcpose::tools {

namespace {

struct HwWorkloadArgs {
  std::string dataset, out;
  std::vector<int> objects;
  int samples = 620;
  uint64_t seed = 0;
};

Status RunHwWorkload(const HwWorkloadArgs& a) {
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> dataset, Dataset::Open(a.dataset, "test", ""));
  bench::BenchOptions options;
  options.obj_ids = a.objects;
  options.estimator.samples = a.samples;
  options.estimator.seed = a.seed;
  std::ostringstream text;
  MCPOSE_ASSIGN_OR_RETURN(const int64_t samples, bench::WriteHardwareWorkload(*dataset, options, text));
  MCPOSE_RETURN_IF_ERROR(io::WriteFileAtomic(a.out, text.str()));
  std::fprintf(stderr, "hw-workload: %lld samples written to %s\n", static_cast<long long>(samples), a.out.c_str());
  return Status::Ok();
}

}  // namespace

void AddHwWorkloadCommand(CLI::App& app, Status* status) {
  auto args = std::make_shared<HwWorkloadArgs>();
  CLI::App* cmd = app.add_subcommand(
      "hw-workload",
      "The initial hypotheses of one `mcpose bench` iteration in the hardware raster core's formats, with the C++ "
      "model's counts (engine hw): the workload scripts/hw.sh workload replays through the RTL");
  cmd->add_option("--dataset", args->dataset, "Dataset root (YCB-Video native or BOP layout)")->required();
  cmd->add_option("--out", args->out, "Workload file to write (text; written whole or not at all)")->required();
  cmd->add_option("--objects", args->objects, "obj_ids (default: the paper's five: 2 4 5 9 10)");
  cmd->add_option("--samples", args->samples, "Samples per object")->check(CLI::Range(1, 100000))->capture_default_str();
  cmd->add_option("--seed", args->seed, "Random seed of the samples")->check(SeedCheck())->capture_default_str();
  cmd->callback([args, status] { *status = RunHwWorkload(*args); });
}

}  // namespace mcpose::tools
