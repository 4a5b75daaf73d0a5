#include "granpack/io/state_parameters.h"

namespace granpack {

ContactLawParams contact_law_params(const MaterialSpec& m) {
  ContactLawParams p;
  if (m.normal_law == "hertz") {
    p.normal = NormalLawKind::kHertz;
    p.young_modulus = m.young_modulus;
    p.poisson_ratio = m.poisson_ratio;
    p.tangential = TangentialStiffnessKind::kMindlin;
  } else {
    p.normal = NormalLawKind::kLinear;
    p.k_n = m.normal_stiffness;
    p.tangential = TangentialStiffnessKind::kRatio;
    p.k_t_ratio = m.tangential_stiffness_ratio;
  }
  p.damping_ratio = m.damping;
  p.damping_tension = m.damping_tension;
  p.walton_rescaling = m.walton_rescaling;
  p.friction = m.friction;
  p.cohesion_force = m.cohesion_force;
  p.cohesion_range = m.cohesion_range;
  p.rolling_stiffness = m.rolling_stiffness;
  p.rolling_friction = m.rolling_friction;
  p.rolling_damping = m.rolling_damping;
  return p;
}

StateParameters replayed_parameters(const Deck& deck, int stage_index) {
  MaterialSpec m = deck.material;
  StressTarget target;
  const int dim = deck.sample.dimension;
  for (const auto& st : deck.stages) {
    if (st.index > stage_index)
      break;
    if (const auto* s = std::get_if<SetStage>(&st.params)) {
      if (s->friction)
        m.friction = *s->friction;
      if (s->damping)
        m.damping = *s->damping;
      if (s->rolling_damping)
        m.rolling_damping = *s->rolling_damping;
    } else if (const auto* f = std::get_if<StiffenStage>(&st.params)) {
      if (f->scale_rolling)
        m.rolling_stiffness *= f->normal_stiffness / m.normal_stiffness;
      m.normal_stiffness = f->normal_stiffness;
    } else if (const auto* c = std::get_if<CompressStage>(&st.params)) {
      // As the analyses of these files always did: a stage with a fixed axis leaves the
      // earlier target in place.
      bool all = true; // every axis stress-controlled
      for (int a = 0; a < dim; ++a)
        if (!c->fixed.empty() && c->fixed[a])
          all = false;
      if (c->stress.size() == std::size_t(dim) && all)
        target = StressTarget{st.index, c->stress, std::vector<bool>(dim, false), c->pressure};
    } else if (std::holds_alternative<PressureStepsStage>(st.params)) {
      target = StressTarget{};
    }
  }
  return {contact_law_params(m), target};
}

} // namespace granpack
