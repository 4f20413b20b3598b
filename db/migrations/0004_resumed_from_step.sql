-- Schema version 4: an attempt that continued from a checkpoint.
--
-- resumed_from_step: the step of the checkpoint an attempt continued from
-- (the solver's result.json "restarted_from_step"), when the runner retried a
-- job that had stopped early (timeout, killed runner, node failure) and an
-- earlier attempt had left checkpoints (output.checkpoint_every); NULL for an
-- attempt that started from step 0.  See db/README.md and docs/campaign.md.
ALTER TABLE runs ADD COLUMN resumed_from_step INTEGER;
