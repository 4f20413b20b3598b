-- Schema version 10: an index of the attempts in Slurm that are running
-- (or queued) now.
--
-- `cascade status STUDY` says how many of a study's running jobs Slurm
-- holds as queued and as running.  It found them by walking every running
-- job of the study and looking up its run: on the bench's database of
-- 1,000,000 jobs (10,000 of them running, none in Slurm) that was 10,000
-- scattered reads of runs, nearly all of the command's time (0.48 s of
-- 0.6 at a load of 40).  This partial index holds only the runs with a
-- Slurm id and status 'running' -- a few thousand at most, none outside
-- Slurm -- so status reads it instead (campaign/cmd_status.c).  SQLite
-- keeps it as runs change status.  IF NOT EXISTS: applying this file to a
-- database that already has the index changes nothing.
CREATE INDEX IF NOT EXISTS runs_slurm_running ON runs (job_id)
    WHERE slurm_job_id IS NOT NULL AND status = 'running';
