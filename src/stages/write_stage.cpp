// `write` stage and the shared writer of configuration files.

#include "granpack/core/error.h"
#include "granpack/io/hdf5_store.h"
#include "granpack/stages/stages.h"

namespace granpack {

template <int dim> void write_state(RunContext<dim>& ctx, const std::filesystem::path& file,
                                    const std::string& run_state) {
  Configuration<dim> c;
  c.cell = ctx.system.cell;
  c.particles = ctx.system.particles;
  c.particles.clear_ghosts();
  c.contacts = ctx.system.contacts;
  // Entries reset when a contact opened (age 0) wait in the store for the next compaction;
  // they are not contacts.
  c.contacts.erase_if([](const ContactKey&, const ContactState<dim>& s) { return s.age == 0; });
  c.meta.granpack_version = GRANPACK_VERSION;
  c.meta.dimension = dim;
  c.meta.time = ctx.system.time;
  c.meta.step = ctx.system.step;
  c.meta.stage_index = ctx.stage_index;
  c.meta.stage_name = ctx.stage_name;
  c.meta.deck_text = ctx.deck->text;
  c.meta.kind = run_state.empty() ? "configuration" : "checkpoint";
  c.meta.run_state = run_state;
  c.meta.parameters = ctx.parameters();
  write_configuration<dim>(ctx.world, file, c);
}

template <int dim> StageReport run_write(RunContext<dim>& ctx, const WriteStage& p) {
  GRANPACK_CHECK(ctx.decomposition, "stage " << ctx.stage_index
                                             << " (write): there is no sample yet; put a "
                                                "lattice or random stage before it");
  write_state(ctx, ctx.output_dir / p.file);
  ctx.log->info("  wrote " + (ctx.output_dir / p.file).string());
  return StageReport{};
}

template void write_state<2>(RunContext<2>&, const std::filesystem::path&, const std::string&);
template void write_state<3>(RunContext<3>&, const std::filesystem::path&, const std::string&);
template StageReport run_write<2>(RunContext<2>&, const WriteStage&);
template StageReport run_write<3>(RunContext<3>&, const WriteStage&);

}  // namespace granpack
