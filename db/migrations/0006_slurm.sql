-- Schema version 6: attempts run by the Slurm backend.
--
-- slurm_job_id: the Slurm id of the attempt, "ARRAY_TASK" as `sbatch
-- --parsable` and `squeue` give it (e.g. '4711_3'), recorded before the
-- array is released to run, so a runner that dies finds it again (and never
-- submits the attempt twice); NULL for attempts run locally or under mpirun.
-- slurm_state: the Slurm state the attempt ended in (COMPLETED, FAILED,
-- TIMEOUT, OUT_OF_MEMORY, NODE_FAIL, PREEMPTED, CANCELLED, ...), NULL while
-- it runs and for attempts outside Slurm.  The node list goes to runs.host,
-- the elapsed time to wall_s, MaxRSS (when accounting has it) to peak_rss_mib.
-- See db/README.md and docs/campaign.md.
ALTER TABLE runs ADD COLUMN slurm_job_id TEXT;
ALTER TABLE runs ADD COLUMN slurm_state TEXT;
CREATE INDEX runs_slurm ON runs (slurm_job_id) WHERE slurm_job_id IS NOT NULL;
