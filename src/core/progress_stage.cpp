// The stage a long piece of work is in, told to whoever opened a scope (progress_stage.hpp).
#include "core/progress_stage.hpp"

#include <utility>

namespace shellcontract {
namespace {

thread_local const ProgressStageScope* current_scope = nullptr;

}  // namespace

ProgressStageScope::ProgressStageScope(std::function<void(const std::string&)> tell)
    : tell_(std::move(tell)), previous_(current_scope) {
  current_scope = this;
}

ProgressStageScope::~ProgressStageScope() { current_scope = previous_; }

void progress_stage(const std::string& what) {
  if (const ProgressStageScope* s = current_scope; s && s->tell_) s->tell_(what);
}

}  // namespace shellcontract
