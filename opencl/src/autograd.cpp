#include "simpli/ocl/autograd.h"

#include "simpli/error.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"

#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace simpli::ocl {

namespace {
thread_local bool gradEnabled = true;
} // namespace

bool GradMode::enabled() {
  return gradEnabled;
}
void GradMode::setEnabled(bool enabled) {
  gradEnabled = enabled;
}

bool needsGrad(const std::vector<Tensor>& inputs) {
  if (!gradEnabled)
    return false;
  for (const auto& t : inputs)
    if (t.requiresGrad())
      return true;
  return false;
}

Tensor record(const char* name, Tensor output, const std::vector<Tensor>& inputs,
              std::function<std::vector<Tensor>(const Tensor& gradOutput)> backward) {
  if (!needsGrad(inputs))
    return output;
  auto node = std::make_shared<Node>();
  node->name = name;
  node->inputs.reserve(inputs.size());
  for (const auto& t : inputs)
    node->inputs.push_back(t.requiresGrad() ? t : Tensor());
  node->backward = std::move(backward);
  output.impl()->gradFn = std::move(node);
  output.impl()->requiresGrad = true;
  return output;
}

namespace {

// Reverse topological order of the impls reachable from root through recorded nodes.
std::vector<TensorImpl*> tapeOrder(TensorImpl* root) {
  std::vector<TensorImpl*> order;
  std::unordered_set<TensorImpl*> visited;
  // Iterative post-order DFS: deep networks would overflow a recursive one.
  std::vector<std::pair<TensorImpl*, std::size_t>> stack{{root, 0}};
  visited.insert(root);
  while (!stack.empty()) {
    auto& [impl, next] = stack.back();
    const auto* node = impl->gradFn.get();
    if (node && next < node->inputs.size()) {
      const Tensor& in = node->inputs[next++];
      if (in.defined() && visited.insert(in.impl().get()).second)
        stack.push_back({in.impl().get(), 0});
      continue;
    }
    order.push_back(impl);
    stack.pop_back();
  }
  return {order.rbegin(), order.rend()};
}

} // namespace

void Tensor::backward() const {
  if (numel() != 1)
    fail("backward: called on ", describe(),
         " which is not a scalar; pass the output gradient explicitly");
  backward(Tensor::ones(shape(), dtype()));
}

void Tensor::backward(const Tensor& gradOutput) const {
  if (!requiresGrad())
    fail("backward: tensor ", describe(),
         " does not require gradients (no parameter or input on its tape requires them)");
  if (gradOutput.shape() != shape() || gradOutput.dtype() != dtype())
    fail("backward: output gradient ", gradOutput.describe(), " does not match ", describe());
  NoGradGuard noGrad; // gradients of gradients are not recorded
  std::unordered_map<TensorImpl*, Tensor> grads;
  grads[impl_.get()] = gradOutput;
  for (TensorImpl* impl : tapeOrder(impl_.get())) {
    auto it = grads.find(impl);
    if (it == grads.end())
      continue;
    Tensor g = it->second;
    grads.erase(it);
    if (!impl->gradFn) {
      if (!impl->requiresGrad)
        continue;
      if (impl->grad)
        Tensor(impl->grad).addInPlace(g);
      else
        impl->grad = g.clone().impl();
      continue;
    }
    const Node& node = *impl->gradFn;
    std::vector<Tensor> inputGrads = node.backward(g);
    if (inputGrads.size() != node.inputs.size())
      fail("backward of op '", node.name, "' returned ", inputGrads.size(), " gradients for ",
           node.inputs.size(), " inputs");
    for (std::size_t i = 0; i < node.inputs.size(); ++i) {
      const Tensor& in = node.inputs[i];
      if (!in.defined() || !inputGrads[i].defined())
        continue;
      if (inputGrads[i].shape() != in.shape())
        fail("backward of op '", node.name, "': gradient ", inputGrads[i].describe(), " for input ",
             i, " of shape ", toString(in.shape()));
      auto [slot, inserted] = grads.try_emplace(in.impl().get(), inputGrads[i]);
      if (!inserted)
        slot->second = add(slot->second, inputGrads[i]);
    }
  }
}

double clipGradNorm(const std::vector<Tensor>& parameters, double maxNorm) {
  NoGradGuard noGrad;
  double total = 0.0;
  for (const auto& p : parameters) {
    Tensor g = p.grad();
    if (g.defined() && g.numel() > 0)
      total += sumAll(mul(g, g)).item();
  }
  const double norm = std::sqrt(total);
  if (norm > maxNorm && norm > 0.0) {
    const double scale = maxNorm / (norm + 1e-6);
    for (const auto& p : parameters) {
      Tensor g = p.grad();
      if (g.defined())
        g.mulInPlace(scale);
    }
  }
  return norm;
}

} // namespace simpli::ocl
