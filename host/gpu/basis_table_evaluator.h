#pragma once
#include <shapespline/core/sample_grid.h>
#include <shapespline/core/span_basis.h>
#include <shapespline/gpu/evaluator_options.h>
#include <shapespline/vk/context.h>

#include <memory>
#include <span>
#include <vector>

namespace shapespline::gpu {

class KernelSet;

// B_r, B_r', B_r'' of a SpanBasis at N uniform parameters t_a = a/(N-1) (basis_table.comp); the
// same table the grid kernels read. Row a of the result holds values[0..m), d1[0..m), d2[0..m).
class BasisTableEvaluator {
 public:
  BasisTableEvaluator(std::shared_ptr<vk::Context> ctx, Precision precision, EvaluatorOptions options = {});
  ~BasisTableEvaluator();
  // Returns N * 3 * m values (layout.h TABLE layout).
  std::vector<double> evaluate(const SpanBasis& basis, int sampleCount);
  // The same at arbitrary parameters t (each in [0,1]).
  std::vector<double> evaluateAt(const SpanBasis& basis, std::span<const double> t);

 private:
  std::vector<double> run(const SpanBasis& basis, int sampleCount, std::span<const double> list);
  std::unique_ptr<KernelSet> kernels_;
};

}  // namespace shapespline::gpu
