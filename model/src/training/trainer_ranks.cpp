// The trainer's data-parallel parts (training/trainer.h): what rank 0 shares at the start, the
// sample streams in checkpoints and on a resume with another number of streams.
#include "simpli/model/training/trainer.h"

#include "simpli/error.h"
#include "simpli/model/training/checkpoint.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <sstream>

namespace simpli::training {

namespace {
using json = nlohmann::json;

std::string stateText(const TrainRandom::State& state) {
  TrainRandom r;
  r.setState(state);
  return r.stateString();
}
} // namespace

void Trainer::shareConfig() {
  if (comm_->size() == 1)
    return;
  std::string text = comm_->isRoot() ? toJson(config_) : std::string();
  comm_->broadcast(text);
  if (!comm_->isRoot())
    config_ = parseTrainingConfig(text, "the training config from rank 0", ".");
}

void Trainer::shareStartState(const std::vector<TrainRandom::State>& rootStreams) {
  std::vector<TrainRandom::State> streams = rootStreams;
  network::ParameterStore& store = network_->parameters();
  const std::vector<ocl::Tensor> params = store.parameters();
  if (comm_->size() > 1) {
    // A small JSON header (step, counts, stream states: 64-bit words) and one buffer of
    // doubles (weights, then the Adam moments that exist), two broadcasts in all.
    std::string header;
    std::vector<double> values;
    if (comm_->isRoot()) {
      const ocl::Adam::State adam = adam_->exportState();
      json h;
      h["step"] = step_;
      h["adam_steps"] = adam.steps;
      json paramSteps = json::array(), moments = json::array(), texts = json::array();
      for (const ocl::Tensor& p : params) {
        const std::vector<double> v = p.toVector();
        values.insert(values.end(), v.begin(), v.end());
      }
      for (const ocl::Adam::ParamState& p : adam.params) {
        paramSteps.push_back(p.step);
        moments.push_back(!p.m.empty());
        values.insert(values.end(), p.m.begin(), p.m.end());
        values.insert(values.end(), p.v.begin(), p.v.end());
      }
      for (const TrainRandom::State& s : streams)
        texts.push_back(stateText(s));
      h["param_steps"] = paramSteps;
      h["moments"] = moments;
      h["streams"] = texts;
      header = h.dump();
    }
    comm_->broadcast(header);
    comm_->broadcast(values);
    if (!comm_->isRoot()) {
      const json h = json::parse(header);
      size_t at = 0;
      auto take = [&](size_t n) {
        if (at + n > values.size())
          fail("trainer: the start state from rank 0 has ", values.size(), " values, too few");
        std::vector<double> part(values.begin() + long(at), values.begin() + long(at + n));
        at += n;
        return part;
      };
      for (ocl::Tensor p : params)
        p.copyFromHost(take(size_t(p.numel())));
      ocl::Adam::State adam;
      adam.steps = h.at("adam_steps").get<int64_t>();
      for (size_t i = 0; i < params.size(); ++i) {
        ocl::Adam::ParamState p;
        p.step = h.at("param_steps").at(i).get<int64_t>();
        if (h.at("moments").at(i).get<bool>()) {
          p.m = take(size_t(params[i].numel()));
          p.v = take(size_t(params[i].numel()));
        }
        adam.params.push_back(std::move(p));
      }
      adam_->importState(adam);
      step_ = h.at("step").get<int64_t>();
      streams.clear();
      for (const json& t : h.at("streams"))
        streams.push_back(TrainRandom::parseState(t.get<std::string>(), "rank 0's streams"));
    }
  }
  const size_t first = size_t(comm_->rank()) * samplers_.size();
  if (streams.size() != size_t(comm_->size()) * samplers_.size())
    fail("trainer: ", streams.size(), " sample streams for ", comm_->size(), " rank(s) x ",
         samplers_.size(), " samples");
  for (size_t j = 0; j < samplers_.size(); ++j)
    samplers_[j].random().setState(streams[first + j]);
}

std::vector<TrainRandom::State> Trainer::gatherStreams() {
  std::string mine;
  for (Sampler& s : samplers_)
    mine += s.random().stateString() + "\n";
  const std::vector<std::string> texts = comm_->gather(mine);
  std::vector<TrainRandom::State> streams;
  for (const std::string& text : texts) {
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line))
      streams.push_back(TrainRandom::parseState(line, "the ranks' sample streams"));
  }
  return streams;
}

void Trainer::resumeStreams(const CheckpointData& c, std::vector<TrainRandom::State>& streams) {
  const std::vector<TrainRandom::State> saved =
      c.streams.empty() ? std::vector<TrainRandom::State>{c.random} : c.streams;
  const size_t now = streams.size(), before = saved.size();
  for (size_t s = 0; s < std::min(now, before); ++s)
    streams[s] = saved[s];
  if (now == before)
    return;
  // Same streams where both have them; new ones start at their fresh (never used) states.
  std::ostringstream m;
  m << "--resume: the checkpoint has " << before << " sample stream(s), this run has " << now
    << " (" << comm_->size() << " rank(s) x " << options_.samplesPerRank
    << " sample(s) per rank): streams 0.." << std::min(now, before) - 1 << " continue";
  if (now > before)
    m << ", streams " << before << ".." << now - 1 << " start fresh";
  else
    m << ", streams " << now << ".." << before - 1 << " are dropped";
  m << "; each step now averages " << now << " sample(s) instead of " << before
    << ", so the run no longer repeats an uninterrupted run with " << before
    << " (the step count, learning rate schedule and weights carry on)";
  say(m.str());
}

} // namespace simpli::training
