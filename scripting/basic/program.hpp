// A loaded MC BASIC program (faulhaber.md §9): the compact form the loader produces and the
// interpreter runs — flat instructions with resolved jump targets and expressions in reverse Polish
// notation, so that running a program does no string processing at all.
//
// Pure value type; the loader (loader.hpp) is the only producer. Invariants the loader guarantees:
// every jump target and expression range is inside the vectors, the code ends with Op::end, every
// instruction that moves backwards (GOTO, GOSUB, RETURN, NEXT, the statement of a one-line IF) is
// either a statement itself (`cost` 1) or directly preceded by the condition that guards it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace mcemu::basic {

// Limits of §9.1/§9.5 and of this implementation.
inline constexpr std::size_t k_max_program_bytes = 4096;
inline constexpr int k_max_if_nesting = 15;
inline constexpr int k_max_gosub_depth = 16;
inline constexpr int k_variable_count = 26;                // a … z = 0x3005.01 … .1A
inline constexpr std::uint16_t k_variable_index = 0x3005;  // the variables' object
inline constexpr std::uint16_t k_status_index = 0x2324;    // device status word (events)
inline constexpr std::uint8_t k_status_sub = 0x01;
inline constexpr int k_max_expression_nesting = 64;  // parentheses and unary operators
inline constexpr int k_max_expression_stack = 256;   // evaluation stack slots

// One step of an expression in reverse Polish notation.
enum class X : std::uint8_t {
  constant,  // push value
  variable,  // push variable `value` (0 = a)
  getobj,    // push GETOBJ index.sub
  neg,
  bnot,  // ~
  mul,
  div,
  mod,
  add,
  sub,
  band,  // &
  bor,   // |
  eq,
  ne,
  lt,
  gt,
  le,
  ge,
  lnot,  // NOT
  land,  // AND
  lor,   // OR
};

struct XOp {
  X op = X::constant;
  std::uint8_t sub = 0;
  std::uint16_t index = 0;
  std::int32_t value = 0;
};

// [begin, end) of Program::expr.
struct ExprRange {
  std::uint32_t begin = 0;
  std::uint32_t end = 0;
};

enum class Op : std::uint8_t {
  assign,         // var := a
  setobj,         // index.sub := a
  jump,           // pc := target (GOTO; also the free jump from a branch's end to its ENDIF)
  jump_if_false,  // IF/ELSEIF condition a: false → pc := target
  gosub,          // push pc+1, pc := target
  ret,            // RETURN
  for_init,       // FOR: loop `slot` of Program::loops
  next,           // NEXT: loop `slot`
  en_evt,         // mask a, handler target
  di_evt,
  def_evt_var,  // var
  ret_evt,
  def_tim_var,  // var
  start_tim,    // a
  def_cyc_var,  // var
  start_cyc,
  stop_cyc,
  save,  // variables list_begin … list_end of Program::lists
  load,
  end,  // end of the text: the program stops normally
};

struct Instr {
  Op op = Op::end;
  std::uint8_t cost = 0;  // 1 = a statement of the budget (and an event check before it); 0 = free
  std::uint8_t var = 0;   // 0 = a … 25 = z
  std::uint8_t sub = 0;
  std::uint16_t index = 0;
  std::uint32_t line = 0;    // 1-based source line
  std::uint32_t target = 0;  // jump target / loop exit (for_init) / loop body (next) / handler
  std::uint32_t slot = 0;    // loop number (for_init, next); list begin (save/load)
  std::uint32_t count = 0;   // list length (save/load)
  ExprRange a{};
};

// FOR v = from TO to [STEP step]: the bounds are evaluated once, when the FOR statement runs.
struct Loop {
  std::uint8_t var = 0;
  bool has_step = false;
  ExprRange from{}, to{}, step{};
};

struct Program {
  std::vector<Instr> code;
  std::vector<XOp> expr;
  std::vector<Loop> loops;
  std::vector<std::uint8_t> lists;  // SAVE/LOAD variable lists
  std::uint32_t lines = 0;          // lines in the source
  std::size_t bytes = 0;            // source size
  std::size_t statements = 0;       // instructions of cost 1
};

}  // namespace mcemu::basic
