#include <shapespline/gpu/basis_table_evaluator.h>

#include <shapespline/gpu/kernel_runs.h>
#include <shapespline/gpu/kernels.h>
#include <shapespline/gpu/list_packing.h>
#include <shapespline/shaders/layout.h>
#include <shapespline/vk/submit.h>

#include <stdexcept>

namespace shapespline::gpu {

BasisTableEvaluator::BasisTableEvaluator(std::shared_ptr<vk::Context> ctx, Precision precision,
                                         EvaluatorOptions options)
    : kernels_(std::make_unique<KernelSet>(std::move(ctx), precision, options.workgroupSize, options.packedStores)) {}
BasisTableEvaluator::~BasisTableEvaluator() = default;

std::vector<double> BasisTableEvaluator::evaluate(const SpanBasis& basis, int sampleCount) {
  return run(basis, sampleCount, {});
}

std::vector<double> BasisTableEvaluator::evaluateAt(const SpanBasis& basis, std::span<const double> t) {
  if (t.empty()) return {};
  return run(basis, static_cast<int>(t.size()), t);
}

std::vector<double> BasisTableEvaluator::run(const SpanBasis& basis, int sampleCount, std::span<const double> list) {
  if (sampleCount < 1) throw std::invalid_argument("BasisTableEvaluator: sampleCount must be >= 1");
  KernelSet& k = *kernels_;
  vk::Buffer sampleBuf;
  if (!list.empty()) {
    std::vector<layout::ListSampleD> s(list.size());
    for (size_t i = 0; i < list.size(); ++i) s[i].u = list[i];
    const std::vector<std::byte> bytes = packListSamples(s, k.precision());
    sampleBuf = vk::Buffer::create(k.context(), bytes.size(), vk::kStorageUsage, vk::MemoryUse::Upload, "gpu.samples");
    sampleBuf.upload(bytes);
  }
  std::vector<double> coef(layout::kParamHeader, 0.0);
  for (int r = 0; r < basis.count; ++r)
    for (int d = 0; d <= basis.degree; ++d) coef[r * layout::kCoefStride + d] = basis.coef[r][d];
  vk::Buffer params = realBuffer(k, coef.size(), vk::MemoryUse::Upload, "gpu.table_params");
  params.upload(toReal(coef, k.precision()));
  const size_t n = size_t(sampleCount) * 3 * basis.count;
  vk::Buffer table = realBuffer(k, n, vk::MemoryUse::Readback, "gpu.table");
  const auto& pipe = k.pipeline(Kernel::BasisTable, basisTableSpec(basis));
  vk::DescriptorSet set = makeSet(k, pipe);
  set.bind(layout::kBindingParams, params).bind(layout::kBindingTable, table);
  if (!list.empty()) set.bind(layout::kBindingSamples, sampleBuf);
  layout::TablePush pc{uint32_t(sampleCount), list.empty() ? 0u : 1u, layout::kParamCoefU, 0u};
  vk::runOneShot(k.context(), [&](VkCommandBuffer cmd) {
    pipe.bind(cmd, set.handle());
    pipe.push(cmd, pc);
    k.dispatch(cmd, uint64_t(sampleCount));
  });
  std::vector<double> out(n);
  const std::byte* p = table.mapped();
  std::vector<std::byte> tmp;
  if (!p) {
    tmp.resize(table.size());
    table.download(tmp);
    p = tmp.data();
  }
  readReals(p, k.precision(), n, out.data());
  return out;
}

}  // namespace shapespline::gpu
