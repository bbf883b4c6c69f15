// Op codes of the elementwise kernels, included by kernels/elementwise.cl (ProgramCache splices
// the embedded header in at `#include "elementwise_op_codes.h"`) and by
// src/ops_elementwise.cpp, so host and kernels cannot disagree. Plain macros: valid C++ and
// OpenCL C.
#ifndef SIMPLI_ELEMENTWISE_OP_CODES_H
#define SIMPLI_ELEMENTWISE_OP_CODES_H

// Binary ops: out = a OP b (broadcasting).
#define OP_ADD 0
#define OP_SUB 1
#define OP_MUL 2
#define OP_DIV 3
#define OP_MAX 4
#define OP_MIN 5
#define OP_GE 6
#define OP_LE 7

// Unary ops: out = f(x), scalar parameters p0, p1 where the op has them.
#define U_NEG 0
#define U_EXP 1
#define U_LOG 2
#define U_SQRT 3
#define U_SQUARE 4
#define U_ABS 5
#define U_RELU 6
#define U_ELU 7
#define U_SIGMOID 8
#define U_TANH 9
#define U_SOFTPLUS 10
#define U_ADD_SCALAR 11
#define U_MUL_SCALAR 12
#define U_CLAMP 13
#define U_POW_SCALAR 14

#endif
