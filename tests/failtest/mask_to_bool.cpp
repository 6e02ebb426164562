// tests/failtest/mask_to_bool.cpp -- must NOT compile: a traced mask cannot drive a branch
#include "quadcast/codegen/expr.hpp"

int main() {
    quadcast::codegen::Recorder rec;
    quadcast::codegen::Recording scope(rec);
    quadcast::codegen::Expr a(1.0f), b(2.0f);
    if (a < b) return 1;
    return 0;
}
