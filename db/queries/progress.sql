-- Jobs per study and state (what `cascade status` shows), plain SQL.
--   cascade query -f db/queries/progress.sql
SELECT s.name AS study, j.state AS state, count(*) AS jobs
FROM jobs j JOIN studies s ON s.id = j.study_id
WHERE j.active = 1
GROUP BY s.name, j.state
ORDER BY s.name, j.state;
