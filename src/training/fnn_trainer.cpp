// placeholder: written by the trainer pass
