// quadcast/codegen/src/interpret.cpp -- CPU evaluation of a recorded DAG
#include "quadcast/codegen/interpret.hpp"

#include <bit>
#include <cmath>
#include <stdexcept>

namespace quadcast::codegen {

TracedKernel::TracedKernel(const KernelDef& k) : io_(rec_) {
    Recording scope(rec_);
    k.trace(io_);
}

void TracedKernel::run(std::span<const std::uint32_t> in, std::span<std::uint32_t> out) {
    const std::size_t n = rec_.size();
    values_.assign(n, 0);
    auto f = [&](std::uint32_t id) { return std::bit_cast<float>(values_[id]); };
    auto b = [&](std::uint32_t id) { return values_[id] != 0; };
    auto F = [](float v) { return std::bit_cast<std::uint32_t>(v); };
    auto B = [](bool v) { return v ? 1u : 0u; };
    // Inputs were created in declaration order, so input index == flat input word.
    for (std::uint32_t id = 1; id < n; ++id) {
        const Node& nd = rec_.node(id);
        std::uint32_t& v = values_[id];
        switch (nd.op) {
        case Op::input: v = in[nd.lit]; break;
        case Op::literal: v = nd.lit; break;
        case Op::add: v = F(f(nd.a) + f(nd.b)); break;
        case Op::sub: v = F(f(nd.a) - f(nd.b)); break;
        case Op::mul: v = F(f(nd.a) * f(nd.b)); break;
        case Op::div: v = F(f(nd.a) / f(nd.b)); break;
        case Op::neg: v = F(-f(nd.a)); break;
        case Op::sqrt: v = F(std::sqrt(f(nd.a))); break;
        case Op::abs: v = F(std::fabs(f(nd.a))); break;
        case Op::floor: v = F(std::floor(f(nd.a))); break;
        case Op::lt: v = B(f(nd.a) < f(nd.b)); break;
        case Op::le: v = B(f(nd.a) <= f(nd.b)); break;
        case Op::gt: v = B(f(nd.a) > f(nd.b)); break;
        case Op::ge: v = B(f(nd.a) >= f(nd.b)); break;
        case Op::eq: v = rec_.node(nd.a).type == Type::boolean ? B(b(nd.a) == b(nd.b)) : B(f(nd.a) == f(nd.b)); break;
        case Op::ne: v = rec_.node(nd.a).type == Type::boolean ? B(b(nd.a) != b(nd.b)) : B(f(nd.a) != f(nd.b)); break;
        case Op::land: v = B(b(nd.a) && b(nd.b)); break;
        case Op::lor: v = B(b(nd.a) || b(nd.b)); break;
        case Op::lnot: v = B(!b(nd.a)); break;
        case Op::select: v = b(nd.a) ? values_[nd.b] : values_[nd.c]; break;
        case Op::isnan: v = B(std::isnan(f(nd.a))); break;
        case Op::isinf: v = B(std::isinf(f(nd.a))); break;
        }
    }
    const auto& outs = io_.output_nodes();
    if (out.size() < outs.size()) throw std::invalid_argument("TracedKernel::run: output span too small");
    for (std::size_t i = 0; i < outs.size(); ++i) out[i] = values_[outs[i]];
}

}  // namespace quadcast::codegen
